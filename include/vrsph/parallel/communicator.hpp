// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Communicator: the set of MPI ranks one computation runs on, as a value without <mpi.h>
// (it keeps the Fortran handle of the MPI communicator). The default is serial: one
// process, no MPI call at all, so nothing needs mpirun. `world()` starts PETSc (and with it
// MPI) on first use and returns PETSC_COMM_WORLD.
//
// Collective error handling: every stage that may throw on some ranks and not on others
// runs through `collective(comm, stage)`. It catches what the stage throws, agrees with the
// other ranks whether any failed, and then throws on *every* rank the typed exception of
// the lowest failing rank, with that rank's message. No rank is left waiting in a
// collective that another rank will never reach: a failure is a clean, common exit.
#include <functional>
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

class Communicator {
 public:
  Communicator() = default;  ///< serial: rank 0 of 1
  /// PETSC_COMM_WORLD (MPI_COMM_WORLD of an mpirun launch; one rank without mpirun).
  /// Throws ConfigError when PETSc/MPI cannot start.
  static Communicator world();
  /// Whether this process was started by an MPI launcher (mpirun/mpiexec) with more than
  /// one rank: read from the launcher's environment, before MPI is started.
  static bool launched_in_parallel();
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }
  bool is_root() const { return rank_ == 0; }
  int fortran_handle() const { return handle_; }  ///< MPI_Comm_c2f of the communicator (internal use)

 private:
  int handle_ = 0;
  int rank_ = 0, size_ = 1;
};

/// Runs `stage` on every rank; if it threw on any rank, throws on all ranks the exception
/// (same type, same message) of the lowest rank that failed. Serial: just runs it.
void collective(const Communicator& comm, const std::function<void()>& stage);

/// Whether `e` is the error `collective` last raised on every rank (the same message there):
/// a caller may then report it once and exit. Any other exception on one rank of several may
/// leave the others waiting in a collective: end them all with abort_all_ranks.
bool raised_on_every_rank(const std::exception& e);
/// Whether every rank of Communicator::world() reaches this call within `seconds` (a
/// non-blocking barrier on a communicator of its own, so that a rank waiting in another
/// collective never matches it). The CLI's error exit: all ranks failed alike (the same bad
/// option), or some rank is elsewhere and abort_all_ranks must end it. Serial: true.
bool every_rank_stops_here(double seconds);
/// Writes `line` to file descriptor 2 (a rank's std::cerr may go nowhere) and ends every rank of
/// `comm` now with exit status `code` (MPI_Abort): the backstop for an error one rank met
/// outside `collective` (docs/parallel.md, "Errors on one rank").
[[noreturn]] void abort_all_ranks(const Communicator& comm, int code, const std::string& line);
/// Test hook: with VRSPH_INJECT_FAULT=STAGE@RANK in the environment, throws NumericalError
/// ("injected fault ...") on that rank when it reaches `stage`; nothing otherwise. The MPI
/// tests use it to prove that a failure in any stage on any rank ends every rank cleanly.
void fault_point(const Communicator& comm, const char* stage);

/// For a stage that makes collective calls of its own (a PETSc solve): `collective` cannot
/// agree on a failure there, since the ranks that did not fail wait inside the stage. On a
/// throw: an error every rank raised (an inner `collective`, or every rank failing alike within
/// seconds) is thrown on every rank as `collective` does; one rank's error alone is printed by
/// that rank (to file descriptor 2, with its rank) and ends every rank through abort_all_ranks
/// with the CLI's exit code of its kind (2 configuration, 3 input, 4 geometry, 5 numerical).
void collective_or_abort(const Communicator& comm, const std::function<void()>& stage);

/// Throws an exception of the same vrsph type as `e` (InputError, GeometryError, ...) with
/// another message: a rank's error reworded (e.g. with global particle numbers).
[[noreturn]] void rethrow_with_message(const std::exception& e, const std::string& message);

// Reductions over the ranks (identities in serial).
double sum_over_ranks(const Communicator& comm, double value);
long long sum_over_ranks(const Communicator& comm, long long value);
double max_over_ranks(const Communicator& comm, double value);
double min_over_ranks(const Communicator& comm, double value);
bool all_ranks(const Communicator& comm, bool value);
bool any_rank(const Communicator& comm, bool value);
/// Exclusive prefix sum over the ranks (0 on rank 0).
long long offset_over_ranks(const Communicator& comm, long long value);
/// Every rank's value, in rank order.
std::vector<long long> gather_over_ranks(const Communicator& comm, long long value);
/// Every rank's values concatenated in rank order, on every rank.
std::vector<double> gather_over_ranks(const Communicator& comm, const std::vector<double>& mine);
/// Consecutive slices of the root's values, `count` of them to this rank (counts in rank
/// order; on_root is read on rank 0 only and must hold their sum). Serial: on_root.
std::vector<double> scatter_from_root(const Communicator& comm, const std::vector<double>& on_root, long long count);
/// Strings from every rank concatenated on every rank in rank order.
std::vector<std::string> gather_strings(const Communicator& comm, const std::vector<std::string>& mine);
/// (value, index) with the largest value; ties: the smallest index.
std::pair<double, long long> max_location_over_ranks(const Communicator& comm, double value, long long index);
/// Elementwise sums of a vector over the ranks (in place).
void sum_over_ranks(const Communicator& comm, std::vector<double>& values);
void sum_over_ranks(const Communicator& comm, std::vector<long long>& values);
void barrier(const Communicator& comm);
/// A barrier whose waiting ranks sleep (1 ms polls) instead of spinning: while rank 0 alone
/// runs a baseline, the other ranks leave it the cores.
void idle_barrier(const Communicator& comm);

}  // namespace vrsph
