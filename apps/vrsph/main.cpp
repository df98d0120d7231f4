// SPDX-License-Identifier: BSD-3-Clause
// vrsph command-line tool. The only place in vrsph that prints errors and decides
// exit codes (docs/errors.md lists every bad-input class with its code and message):
//   0 success (the result was delivered)
//   1 command-line usage: unknown option or subcommand, missing argument (CLI11)
//   2 configuration: a bad option value, unknown method/operator/option, an option
//     that does not apply, or a run larger than the memory limit (ResourceError)
//   3 input data: a bad cloud file or expression, inconsistent boundary data, and any
//     file that cannot be read or written (IoError: missing, a directory, disk full)
//   4 geometry: the cloud does not support the discretisation (isolated particles)
//   5 numerical: a failed local problem (with --on-infeasible error) or linear solve
//  70 internal error: a bug in vrsph (please report it with the command line)
#include <unistd.h>
#include <algorithm>
#include <csignal>
#include <cstdlib>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <fstream>
#include <iostream>
#include <new>
#include <optional>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/threads.hpp>
#include <vrsph/io/output_file.hpp>
#include "cli_common.hpp"
#include "commands.hpp"
#include "relaunch.hpp"

namespace {

// libgomp reads its wait policy when it is loaded, before main(): by default idle
// worker threads spin for a while before sleeping, which on a loaded machine steals
// the cores the other threads need. Unless the user chose a policy, run ourselves
// again with the passive one (threads sleep at once). VRSPH_NO_REEXEC disables this.
void prefer_passive_openmp_threads(char** argv) {
#ifdef _OPENMP
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT") || std::getenv("VRSPH_NO_REEXEC")) return;
  ::setenv("OMP_WAIT_POLICY", "passive", 1);
  ::setenv("VRSPH_NO_REEXEC", "1", 1);
  ::execv("/proc/self/exe", argv);  // returns only on failure: then go on as we are
#else
  (void)argv;
#endif
}

// Ctrl-C, kill or a closed terminal end the run as before (the default action, so the exit
// status still says which signal), but first remove the temporary file of a write in progress:
// the target keeps its previous content and no temporary is left beside it.
void end_on_signal(int sig) {
  vrsph::remove_pending_temporaries();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void clean_up_on_signals() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, end_on_signal);
}

// An error every rank raised together (vrsph::collective, or every rank failing alike) is
// printed once, by rank 0, and every rank exits with the same code. An error one rank met
// alone may leave the others waiting in a collective: that rank prints it itself (its
// std::cerr goes nowhere, so to the file descriptor) and ends every rank with the same code
// (MPI_Abort), never a hang.
int report(const char* kind, const std::exception& e, int code) {
  const auto& comm = vrsph::cli::communicator();
  // Three seconds: ranks that failed alike (a bad option value) arrive within milliseconds.
  if (comm.distributed() && !vrsph::raised_on_every_rank(e) && !vrsph::every_rank_stops_here(3.0)) {
    const std::string line = "vrsph: " + std::string(kind) + " (rank " + std::to_string(comm.rank()) + " of " +
                             std::to_string(comm.size()) + "; every rank stopped): " + e.what() + "\n";
    std::cout.flush();
    vrsph::abort_all_ranks(comm, code, line);
  }
  std::cerr << "vrsph: " << kind << ": " << e.what() << '\n';
  return code;
}

// "vrsph 0.2.0 (BSD-3-Clause)", then the parts built with and without: the version and the optional
// parts of this build, so that a bug report says both.
std::string version_line() {
  std::string with, without;
  for (const vrsph::Part& p : vrsph::parts()) (p.built ? with : without) += " " + std::string(p.name);
  return "vrsph " + std::string(vrsph::version()) + " (BSD-3-Clause)\nbuilt with:" + (with.empty() ? " none" : with) +
         "\nbuilt without:" + (without.empty() ? " none" : without);
}
// Started by mpirun with several ranks: run on MPI_COMM_WORLD; only rank 0 prints (the
// others' standard output goes nowhere; an error is the same on every rank, see
// vrsph::collective, and rank 0 reports it). Returns an exit code if joining failed.
std::optional<int> join_mpi_world() {
  if (!vrsph::Communicator::launched_in_parallel()) return std::nullopt;
  try {
    vrsph::cli::set_communicator(vrsph::Communicator::world());
    vrsph::cli::mark_ranks_started();
  } catch (const vrsph::FeatureUnavailable& e) {
    return report("not in this build", e, 2);
  } catch (const vrsph::ConfigError& e) {
    return report("configuration error", e, 2);
  }
#ifdef _OPENMP
  // One thread per rank's share of the cores unless the user chose (ranks x threads <= cores).
  if (!std::getenv("OMP_NUM_THREADS")) {
    const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    const int ranks_here = local ? std::max(1, std::atoi(local)) : vrsph::cli::communicator().size();
    omp_set_num_threads(std::max(1, omp_get_num_procs() / ranks_here));
  }
#endif
  if (!vrsph::cli::communicator().is_root()) {
    // Never destroyed: the standard streams keep using the buffer until the process ends.
    static auto* const nowhere = new std::ofstream("/dev/null");
    std::cout.rdbuf(nowhere->rdbuf());
    std::cerr.rdbuf(nowhere->rdbuf());
  }
  return std::nullopt;
}

// Under mpirun: the commands with a distributed pipeline; any other would only repeat
// the same serial run on every rank.
void require_distributed_command(const CLI::App& app) {
  const auto& comm = vrsph::cli::communicator();
  if (!comm.distributed()) return;
  const auto subs = app.get_subcommands();
  const std::string name = subs.empty() ? "" : subs.front()->get_name();
  vrsph::check<vrsph::ConfigError>(vrsph::cli::distributed_command(app), "vrsph ", name, " runs on one rank; under mpirun (",
                                   comm.size(), " ranks) only study, solve, diffuse and bench solve are distributed");
}

// The options every command takes (--max-memory, --verbose, --version) and the checks
// that run after parsing, before the subcommand's callback.
struct GlobalOptions {
  std::string max_memory;
  bool verbose = false;
  std::string ranks = "auto";
};

void add_global_options(CLI::App& app, GlobalOptions& g, int argc, char** argv) {
  app.set_version_flag("--version", version_line());
  app.require_subcommand(1);
  app.fallthrough();  // global options may also follow the subcommand
  app.add_option("--max-memory", g.max_memory,
                 "Refuse runs whose estimated memory exceeds this (e.g. 8G, 512M; 0 = no limit; default: the memory "
                 "available when the run starts)");
  app.add_option("--ranks", g.ranks,
                 "Run study, solve, diffuse or bench solve on this many MPI ranks of this machine (vrsph starts "
                 "mpirun itself; one thread per rank): faster than threads for large solves (docs/performance.md). "
                 "auto (default): one rank per core for study, solve and bench solve (without --threads, "
                 "--anchor) runs of at least 150000 particles in 2D or 200000 in 3D solved by PETSc, unless "
                 "OMP_NUM_THREADS is set (VRSPH_RANKS_AUTO_MIN_PARTICLES: another threshold); one process otherwise")
      ->capture_default_str();
  app.add_flag("--verbose", g.verbose, "Warnings with their full lists (e.g. every row that could not meet its moment "
                                       "conditions); without it one line per kind of condition");
  app.parse_complete_callback([&app, &g, argc, argv] {
    vrsph::cli::set_verbose(g.verbose);
    vrsph::cli::reject_empty_values(app);
    vrsph::cli::reject_output_over_input(app);
    require_distributed_command(app);
    vrsph::cli::apply_ranks_option(g.ranks, app, argc, argv);  // a number: returns only when already on that many ranks
    if (app.count("--max-memory")) vrsph::set_memory_limit_bytes(vrsph::parse_memory_size(g.max_memory));
  });
}

void add_commands(CLI::App& app) {
  vrsph::cli::add_methods_command(app);
  vrsph::cli::add_kernels_command(app);
  vrsph::cli::add_cloud_command(app);
  vrsph::cli::add_operator_command(app);
  vrsph::cli::add_study_command(app);
  vrsph::cli::add_solve_command(app);
  vrsph::cli::add_spectrum_command(app);
  vrsph::cli::add_stability_command(app);
  vrsph::cli::add_diffuse_command(app);
  vrsph::cli::add_flow_command(app);
  vrsph::cli::add_bench_command(app);
}

int usage_error(const CLI::ParseError& e, CLI::App& app, int argc, char** argv) {
  // "vrsph frobnicate": CLI11 only says a subcommand is required; name what was given.
  if (dynamic_cast<const CLI::RequiredError*>(&e) && argc > 1 && argv[1][0] != '-' && app.get_subcommands().empty()) {
    std::string known;
    for (const CLI::App* sub : app.get_subcommands({})) known += (known.empty() ? "" : ", ") + sub->get_name();
    std::cerr << "vrsph: unknown command '" << argv[1] << "' (known: " << known << "; vrsph --help)\n";
    return 1;
  }
  const int rc = app.exit(e);
  if (rc == 0) return 0;  // --help, --version
  // A value that does not convert or validate is a configuration error like any
  // other bad option value; only the shape of the command line is a usage error.
  const bool bad_value = dynamic_cast<const CLI::ConversionError*>(&e) || dynamic_cast<const CLI::ValidationError*>(&e);
  return bad_value ? 2 : 1;
}
}  // namespace

int main(int argc, char** argv) {
  prefer_passive_openmp_threads(argv);
  clean_up_on_signals();
  try {
    const std::string warning = vrsph::sanitise_openmp_environment();
    if (!warning.empty()) std::cerr << "vrsph: warning: " << warning << '\n';
  } catch (const vrsph::ConfigError& e) {
    return report("configuration error", e, 2);
  }
  if (const auto failed = join_mpi_world()) return *failed;
  CLI::App app{"vrsph — particle discretisations of elliptic operators on irregular point clouds"};
  GlobalOptions global;
  add_global_options(app, global, argc, argv);
  add_commands(app);
  try {
    app.parse(argc, argv);
    vrsph::cli::print_notes();
    // Whatever a command printed must have reached stdout (a full disk, a closed pipe).
    vrsph::check_stream(std::cout, "to standard output");
  } catch (const CLI::ParseError& e) {
    return usage_error(e, app, argc, argv);
  } catch (const vrsph::ResourceError& e) {
    return report("resource limit", e, 2);
  } catch (const vrsph::FeatureUnavailable& e) {
    return report("not in this build", e, 2);
  } catch (const vrsph::ConfigError& e) {
    return report("configuration error", e, 2);
  } catch (const vrsph::IoError& e) {
    return report("I/O error", e, 3);
  } catch (const vrsph::InputError& e) {
    return report("input error", e, 3);
  } catch (const vrsph::GeometryError& e) {
    return report("geometry error", e, 4);
  } catch (const vrsph::NumericalError& e) {
    return report("numerical error", e, 5);
  } catch (const std::bad_alloc& e) {
    // Our estimates refuse oversized runs before allocating; this is the backstop.
    return report("resource limit",
                  std::runtime_error(std::string("out of memory (") + e.what() +
                                     "); reduce --n or --h-factor, or run on a machine with more memory"),
                  2);
  } catch (const std::exception& e) {
    return report("internal error (a bug in vrsph: please report the command line)", e, 70);
  }
  return 0;
}
