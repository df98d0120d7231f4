// SPDX-License-Identifier: BSD-3-Clause
// MPI behind Communicator: reductions, gathers and the collective error agreement
// (communicator_serial.cpp: the same without MPI).
#include <petscsys.h>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <thread>
#include <exception>
#include <limits>
#include <typeinfo>
#include <vrsph/core/error.hpp>
#include <vrsph/parallel/communicator.hpp>
#include "collective_errors.hpp"
#include "petsc_runtime.hpp"

namespace vrsph {

namespace {
MPI_Comm mpi(const Communicator& c) { return MPI_Comm_f2c(c.fortran_handle()); }

// A duplicate of PETSC_COMM_WORLD for the error exit's barrier only (every_rank_stops_here).
MPI_Comm& exit_communicator() {
  static MPI_Comm c = MPI_COMM_NULL;
  return c;
}
}  // namespace

Communicator Communicator::world() {
  detail::start_petsc();
  if (exit_communicator() == MPI_COMM_NULL) MPI_Comm_dup(PETSC_COMM_WORLD, &exit_communicator());
  Communicator c;
  c.handle_ = static_cast<int>(MPI_Comm_c2f(PETSC_COMM_WORLD));
  MPI_Comm_rank(PETSC_COMM_WORLD, &c.rank_);
  MPI_Comm_size(PETSC_COMM_WORLD, &c.size_);
  return c;
}

void collective(const Communicator& comm, const std::function<void()>& stage) {
  if (!comm.distributed()) {
    stage();
    return;
  }
  auto [kind, message] = detail::run_stage(stage, false);
  // The lowest failing rank speaks for all.
  int mine = kind != detail::None ? comm.rank() : comm.size(), first = 0;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, mpi(comm));
  if (first == comm.size()) return;
  int sizes[2] = {kind, static_cast<int>(message.size())};
  MPI_Bcast(sizes, 2, MPI_INT, first, mpi(comm));
  message.resize(static_cast<std::size_t>(sizes[1]));
  MPI_Bcast(message.data(), sizes[1], MPI_CHAR, first, mpi(comm));
  const std::string agreed = first == 0 ? message : detail::concat("rank ", first, ": ", message);
  detail::last_agreed_message() = agreed;
  detail::rethrow(sizes[0], agreed);
}

bool every_rank_stops_here(double seconds) {
  if (exit_communicator() == MPI_COMM_NULL) return true;
  int size = 1;
  MPI_Comm_size(exit_communicator(), &size);
  if (size == 1) return true;
  MPI_Request request;
  MPI_Ibarrier(exit_communicator(), &request);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int done = 0;
  while (!done && std::chrono::steady_clock::now() < until) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return done != 0;
}

void abort_all_ranks(const Communicator& comm, int code, const std::string& line) {
  if (::write(2, line.data(), line.size()) < 0) {
  }  // nothing else to tell
  if (comm.distributed()) MPI_Abort(mpi(comm), code);
  std::exit(code);
}

double sum_over_ranks(const Communicator& c, double v) {
  if (!c.distributed()) return v;
  double r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_SUM, mpi(c));
  return r;
}
long long sum_over_ranks(const Communicator& c, long long v) {
  if (!c.distributed()) return v;
  long long r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_LONG_LONG, MPI_SUM, mpi(c));
  return r;
}
double max_over_ranks(const Communicator& c, double v) {
  if (!c.distributed()) return v;
  double r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, mpi(c));
  return r;
}
double min_over_ranks(const Communicator& c, double v) {
  if (!c.distributed()) return v;
  double r = 0;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MIN, mpi(c));
  return r;
}
bool all_ranks(const Communicator& c, bool v) {
  if (!c.distributed()) return v;
  int in = v, r = 0;
  MPI_Allreduce(&in, &r, 1, MPI_INT, MPI_LAND, mpi(c));
  return r != 0;
}
bool any_rank(const Communicator& c, bool v) {
  if (!c.distributed()) return v;
  int in = v, r = 0;
  MPI_Allreduce(&in, &r, 1, MPI_INT, MPI_LOR, mpi(c));
  return r != 0;
}
long long offset_over_ranks(const Communicator& c, long long v) {
  if (!c.distributed()) return 0;
  long long r = 0;
  MPI_Exscan(&v, &r, 1, MPI_LONG_LONG, MPI_SUM, mpi(c));
  return c.rank() == 0 ? 0 : r;
}
std::vector<long long> gather_over_ranks(const Communicator& c, long long v) {
  std::vector<long long> all(static_cast<std::size_t>(c.size()), v);
  if (c.distributed()) MPI_Allgather(&v, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, mpi(c));
  return all;
}
namespace {
// Counts and displacements of an MPI v-collective; refuses what an int cannot count.
void v_layout(const std::vector<long long>& sizes, std::vector<int>& counts, std::vector<int>& displs) {
  counts.resize(sizes.size());
  displs.resize(sizes.size());
  long long total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    check<ResourceError>(total + sizes[r] <= std::numeric_limits<int>::max(), "an exchange of ", total + sizes[r],
                         " values exceeds what one MPI call can count (2^31 - 1): use more ranks");
    counts[r] = static_cast<int>(sizes[r]);
    displs[r] = static_cast<int>(total);
    total += sizes[r];
  }
}
}  // namespace

std::vector<double> gather_over_ranks(const Communicator& c, const std::vector<double>& mine) {
  if (!c.distributed()) return mine;
  std::vector<int> counts, displs;
  v_layout(gather_over_ranks(c, static_cast<long long>(mine.size())), counts, displs);
  std::vector<double> all(static_cast<std::size_t>(displs.back() + counts.back()));
  MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                 MPI_DOUBLE, mpi(c));
  return all;
}

std::vector<double> scatter_from_root(const Communicator& c, const std::vector<double>& on_root, long long count) {
  if (!c.distributed()) return on_root;
  std::vector<int> counts, displs;
  v_layout(gather_over_ranks(c, count), counts, displs);
  // (The root's size is the caller's contract: a check on one rank would leave the others waiting.)
  std::vector<double> mine(static_cast<std::size_t>(count));
  MPI_Scatterv(on_root.data(), counts.data(), displs.data(), MPI_DOUBLE, mine.data(), static_cast<int>(count),
               MPI_DOUBLE, 0, mpi(c));
  return mine;
}

std::vector<std::string> gather_strings(const Communicator& c, const std::vector<std::string>& mine) {
  if (!c.distributed()) return mine;
  std::string packed;
  for (const auto& s : mine) packed += s + '\0';
  const std::vector<long long> sizes = gather_over_ranks(c, static_cast<long long>(packed.size()));
  std::vector<int> counts(sizes.size()), displs(sizes.size());
  int total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    counts[r] = static_cast<int>(sizes[r]);
    displs[r] = total;
    total += counts[r];
  }
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Allgatherv(packed.data(), static_cast<int>(packed.size()), MPI_CHAR, all.data(), counts.data(), displs.data(),
                 MPI_CHAR, mpi(c));
  std::vector<std::string> out;
  for (std::size_t at = 0; at < all.size();) {
    const std::size_t end = all.find('\0', at);
    out.push_back(all.substr(at, end - at));
    at = end + 1;
  }
  return out;
}
std::pair<double, long long> max_location_over_ranks(const Communicator& c, double v, long long index) {
  if (!c.distributed()) return {v, index};
  const double best = max_over_ranks(c, v);
  const long long mine = v == best ? index : std::numeric_limits<long long>::max();
  long long r = 0;
  MPI_Allreduce(&mine, &r, 1, MPI_LONG_LONG, MPI_MIN, mpi(c));
  return {best, r};
}
void sum_over_ranks(const Communicator& c, std::vector<double>& v) {
  if (c.distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, mpi(c));
}
void sum_over_ranks(const Communicator& c, std::vector<long long>& v) {
  if (c.distributed()) MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_LONG_LONG, MPI_SUM, mpi(c));
}
void barrier(const Communicator& c) {
  if (c.distributed()) MPI_Barrier(mpi(c));
}
void idle_barrier(const Communicator& c) {
  if (!c.distributed()) return;
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibarrier(mpi(c), &request);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace vrsph
