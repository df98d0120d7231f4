// SPDX-License-Identifier: BSD-3-Clause
// CLI state shared by the commands: the communicator, --verbose, notes printed at the end, threads and peak memory.
#include "cli_common.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <thread>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/methods/registry.hpp>

namespace vrsph::cli {

namespace {
Communicator& the_communicator() {
  static Communicator comm;
  return comm;
}
}  // namespace

const Communicator& communicator() { return the_communicator(); }
void set_communicator(const Communicator& comm) { the_communicator() = comm; }
namespace {
bool& verbose_flag() {
  static bool on = false;
  return on;
}
}  // namespace
bool verbose() { return verbose_flag(); }
namespace {
std::vector<std::string>& pending_notes() {
  static std::vector<std::string> notes;
  return notes;
}
}  // namespace
void note_row_forms(const std::vector<std::string>& methods, const std::map<std::string, MethodOptions>& options,
                    StencilUse use) {
  for (const auto& m : methods) {
    const std::string note = builtin_methods().create(m, options_for(options, m))->row_forms(use);
    if (!note.empty()) pending_notes().push_back(note);
  }
}
void print_notes() {
  for (const auto& n : pending_notes()) std::cerr << "vrsph: note: " << n << '\n';
  pending_notes().clear();
}
void set_verbose(bool on) { verbose_flag() = on; }

void set_thread_count(int threads) {
  check<ConfigError>(threads >= 0, "--threads must be >= 0 (0 = one per core), got ", threads);
#ifdef _OPENMP
  const int cores = omp_get_num_procs();  // those this process may run on
  // 0: one per core, shared among this machine's ranks under mpirun; a number given: at most
  // that share too (ranks x threads above the cores would oversubscribe them: `vrsph --ranks 2
  // ... --threads 2` ran four threads on two cores). A rank bound to fewer cores than the
  // machine has (mpirun binds each rank to its own by default) has them for itself.
  int ranks_here = 1;
  if (communicator().distributed()) {
    const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    ranks_here = local ? std::max(1, std::atoi(local)) : communicator().size();
  }
  const bool bound = cores < static_cast<int>(std::thread::hardware_concurrency());
  const int share = ranks_here > 1 && !bound ? std::max(1, cores / ranks_here) : cores;
  if (threads > share) {
    if (ranks_here > 1)
      std::cerr << "vrsph: warning: --threads " << threads << " is more than the " << share << " core"
                << (share == 1 ? "" : "s") << " each of the " << ranks_here << " ranks on this machine has; using "
                << share << '\n';
    else
      std::cerr << "vrsph: warning: --threads " << threads << " is more than the " << cores
                << " cores of this machine; using " << cores << '\n';
  }
  omp_set_num_threads(threads == 0 ? share : std::min(threads, share));
#else
  if (threads > 1)
    std::cerr << "vrsph: warning: --threads " << threads << " is more than the 1 thread of this build (no OpenMP); using 1\n";
#endif
}

double peak_memory_mib() { return static_cast<double>(peak_resident_memory_bytes()) / (1024.0 * 1024.0); }

}  // namespace vrsph::cli
