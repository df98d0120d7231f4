// SPDX-License-Identifier: BSD-3-Clause
// Communicator in a build without MPI (VRSPH_WITH_MPI=OFF): one process, rank 0 of 1, every
// reduction the identity. Started by mpirun with several ranks, world() refuses rather than
// letting each rank solve the whole problem on its own (communicator.cpp: the MPI one).
#include <unistd.h>

#include <cstdlib>
#include <vrsph/core/features.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph {

Communicator Communicator::world() {
  if (launched_in_parallel()) require_part("MPI", "a run under mpirun with more than one rank");
  return {};
}

void collective(const Communicator&, const std::function<void()>& stage) { stage(); }
bool every_rank_stops_here(double) { return true; }
void abort_all_ranks(const Communicator&, int code, const std::string& line) {
  if (::write(2, line.data(), line.size()) < 0) {
  }  // nothing else to tell
  std::exit(code);
}

double sum_over_ranks(const Communicator&, double v) { return v; }
long long sum_over_ranks(const Communicator&, long long v) { return v; }
double max_over_ranks(const Communicator&, double v) { return v; }
double min_over_ranks(const Communicator&, double v) { return v; }
bool all_ranks(const Communicator&, bool v) { return v; }
bool any_rank(const Communicator&, bool v) { return v; }
long long offset_over_ranks(const Communicator&, long long) { return 0; }
std::vector<long long> gather_over_ranks(const Communicator&, long long v) { return {v}; }
std::vector<double> gather_over_ranks(const Communicator&, const std::vector<double>& mine) { return mine; }
std::vector<double> scatter_from_root(const Communicator&, const std::vector<double>& on_root, long long) {
  return on_root;
}
std::vector<std::string> gather_strings(const Communicator&, const std::vector<std::string>& mine) { return mine; }
std::pair<double, long long> max_location_over_ranks(const Communicator&, double v, long long index) {
  return {v, index};
}
void sum_over_ranks(const Communicator&, std::vector<double>&) {}
void sum_over_ranks(const Communicator&, std::vector<long long>&) {}
void barrier(const Communicator&) {}
void idle_barrier(const Communicator&) {}

}  // namespace vrsph
