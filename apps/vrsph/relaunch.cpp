// SPDX-License-Identifier: BSD-3-Clause
#include "relaunch.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <charconv>
#include <csignal>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include "cli_common.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vrsph::cli {

bool distributed_command(const CLI::App& app) {
  const auto subs = app.get_subcommands();
  const std::string name = subs.empty() ? "" : subs.front()->get_name();
  return name == "study" || name == "solve" || name == "diffuse" ||
         (name == "bench" && !subs.front()->get_subcommands().empty() &&
          subs.front()->get_subcommands().front()->get_name() == "solve");
}

namespace {

int cores_here() {
#ifdef _OPENMP
  return omp_get_num_procs();
#else
  return 1;
#endif
}

bool mpirun_on_path() { return std::system("command -v mpirun >/dev/null 2>&1") == 0; }

std::string this_program() {
  std::error_code ec;
  const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  check<IoError>(!ec && !self.empty(), "--ranks: cannot find this program's path (/proc/self/exe)");
  return self;
}

// mpirun -np <ranks> <this program> <argv without --ranks>, as execvp takes it (the strings
// live in `storage`). quiet: without OpenMPI's banners (an MPI_Abort's, a rank's non-zero
// exit), which a user who did not ask for MPI would only be puzzled by; our own message and
// exit status say what happened.
std::vector<char*> mpirun_command(int ranks, int argc, char** argv, std::vector<std::string>& storage, bool quiet) {
  storage = {"mpirun"};
  if (::geteuid() == 0) storage.emplace_back("--allow-run-as-root");
  if (quiet) storage.emplace_back("--quiet");
  // A slot per logical CPU, as the cores counted here (OpenMP's): OpenMPI counts physical cores
  // by default, and on a machine with two hardware threads per core `-np <CPUs>` would find too
  // few slots.
  storage.emplace_back("--use-hwthread-cpus");
  storage.insert(storage.end(), {"-np", std::to_string(ranks), this_program()});
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--ranks") {
      ++k;  // and its value
      continue;
    }
    if (a.rfind("--ranks=", 0) == 0) continue;
    storage.push_back(a);
  }
  std::vector<char*> c_args;
  for (auto& a : storage) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  return c_args;
}

// --ranks auto: the command line, kept until the command knows its size; and, on the ranks
// it started, that they were started so (mark_ranks_started).
struct AutoRanks {
  bool on = false;
  int argc = 0;
  char** argv = nullptr;
  bool started_here = false;
};
AutoRanks& auto_ranks() {
  static AutoRanks a;
  return a;
}

// The rank 0 of an automatic start writes to this file once it has joined the world: the
// parent then knows the ranks ran (their exit status is the run's) rather than failed to start.
constexpr const char* kStartedFileVariable = "VRSPH_RANKS_STARTED_FILE";

// While the parent waits for mpirun, SIGINT/SIGTERM/SIGHUP go on to mpirun (which stops its
// ranks); the parent then ends by the same signal.
volatile std::sig_atomic_t forwarded_to = 0;
volatile std::sig_atomic_t received_signal = 0;
extern "C" void forward_signal(int sig) {
  received_signal = sig;
  if (forwarded_to > 0) ::kill(static_cast<pid_t>(forwarded_to), sig);
}

// Ends this process by `sig` as its default action would (the parent of vrsph sees the signal).
void end_by_signal(int sig) {
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

}  // namespace

void relaunch_on_ranks(int ranks, const CLI::App& app, int argc, char** argv) {
  check<ConfigError>(ranks >= 1, "--ranks must be >= 1, got ", ranks);
  const Communicator& comm = communicator();
  if (Communicator::launched_in_parallel()) {
    check<ConfigError>(ranks == 1 || ranks == comm.size(), "--ranks ", ranks, " under mpirun with ", comm.size(),
                       " ranks: give the ranks one way, not both");
    return;
  }
  if (ranks == 1) return;
  const auto subs = app.get_subcommands();
  check<ConfigError>(distributed_command(app), "--ranks applies to study, solve, diffuse and bench solve (the "
                     "commands with a distributed pipeline), not to ", subs.empty() ? std::string("no command")
                                                                           : subs.front()->get_name());
  const int cores = cores_here();
  check<ConfigError>(ranks <= cores, "--ranks ", ranks, " is more than this machine's ", cores,
                     " cores (run mpirun yourself to oversubscribe or to use several machines)");
  check<ConfigError>(mpirun_on_path(), "--ranks needs mpirun (Debian's openmpi-bin), which is not on PATH");
  std::vector<std::string> storage;
  const std::vector<char*> c_args = mpirun_command(ranks, argc, argv, storage, false);
  std::cout.flush();
  std::cerr.flush();
  ::execvp("mpirun", c_args.data());
  throw IoError(detail::concat("--ranks: could not start mpirun: ", std::strerror(errno)));
}

void apply_ranks_option(const std::string& value, const CLI::App& app, int argc, char** argv) {
  AutoRanks& a = auto_ranks();
  a.on = value == "auto";
  a.argc = argc;
  a.argv = argv;
  if (a.on) return;
  int ranks = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), ranks);
  check<ConfigError>(ec == std::errc() && end == value.data() + value.size() && ranks >= 1,
                     "--ranks must be auto or a whole number >= 1, got '", value, "'");
  relaunch_on_ranks(ranks, app, argc, argv);
}

int large_run_ranks(Index particles, int dim, int cores, Index min_particles) {
  if (dim < 2 || cores < 2 || particles < min_particles) return 1;
  return cores;
}

Index auto_ranks_min_particles(int dim) {
  const char* v = std::getenv(kAutoRanksMinParticlesVariable);
  if (!v) return dim == 3 ? kAutoRanksMinParticles3d : kAutoRanksMinParticles2d;
  const std::string text(v);
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  check<ConfigError>(ec == std::errc() && end == text.data() + text.size() && value >= 1, kAutoRanksMinParticlesVariable,
                     " must be a whole number of particles >= 1, got '", text, "'");
  return static_cast<Index>(value);
}

bool ranks_started_automatically() { return auto_ranks().started_here; }

void mark_ranks_started() {
  const char* path = std::getenv(kStartedFileVariable);
  if (!path) return;
  auto_ranks().started_here = true;
  if (communicator().is_root()) {
    const int fd = ::open(path, O_WRONLY | O_APPEND);
    if (fd >= 0) {
      if (::write(fd, "1", 1) < 0) {
      }  // nothing to do: the parent then runs the command itself
      ::close(fd);
    }
  }
  ::unsetenv(kStartedFileVariable);  // not for processes this run starts (the peer's mpirun)
}

void run_on_ranks_if_large(Index particles, int dim, bool petsc_solve) {
  const AutoRanks& a = auto_ranks();
  if (!a.on) return;
  const Index min_particles = auto_ranks_min_particles(dim);  // a bad value is refused even where unused
  if (!petsc_solve || Communicator::launched_in_parallel() || std::getenv("OMP_NUM_THREADS") || !built_with("MPI") ||
      !built_with("PETSC"))
    return;
  const int ranks = large_run_ranks(particles, dim, cores_here(), min_particles);
  if (ranks <= 1 || !mpirun_on_path()) return;
  std::vector<std::string> storage;
  std::vector<char*> c_args;
  try {
    c_args = mpirun_command(ranks, a.argc, a.argv, storage, true);
  } catch (const IoError&) {
    return;  // this program's path unknown (no /proc): the run stays in this process
  }
  std::error_code ec;
  std::string marker = (std::filesystem::temp_directory_path(ec) / "vrsph-ranks-XXXXXX").string();
  const int fd = ec ? -1 : ::mkstemp(marker.data());
  if (fd < 0) return;  // no temporary file: run in this process
  ::close(fd);
  std::cerr << "vrsph: note: " << particles << " particles: running on " << ranks << " MPI ranks of one thread each, "
            << "faster than one process for large solves (--ranks 1 keeps one process)\n";
  std::cout.flush();
  std::cerr.flush();
  struct sigaction forward {}, before[3];
  forward.sa_handler = forward_signal;
  sigemptyset(&forward.sa_mask);
  const int signals[3] = {SIGINT, SIGTERM, SIGHUP};
  for (int k = 0; k < 3; ++k) ::sigaction(signals[k], &forward, &before[k]);
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // mpirun ends with this process, however it ends
    if (::getppid() != parent) ::_exit(128 + SIGTERM);
    for (int k = 0; k < 3; ++k) ::sigaction(signals[k], &before[k], nullptr);
    ::setenv(kStartedFileVariable, marker.c_str(), 1);
    ::execvp("mpirun", c_args.data());
    ::_exit(127);
  }
  int status = 0;
  if (child > 0) {
    forwarded_to = child;
    if (received_signal) ::kill(child, received_signal);  // one that came before the fork
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    forwarded_to = 0;
  }
  for (int k = 0; k < 3; ++k) ::sigaction(signals[k], &before[k], nullptr);
  const bool started = child > 0 && std::filesystem::file_size(marker, ec) > 0 && !ec;
  std::filesystem::remove(marker, ec);
  if (received_signal) end_by_signal(received_signal);
  if (started) {
    if (WIFSIGNALED(status)) end_by_signal(WTERMSIG(status));
    std::exit(WIFEXITED(status) ? WEXITSTATUS(status) : 1);
  }
  std::cerr << "vrsph: warning: mpirun could not start " << ranks << " ranks ("
            << (child < 0 ? "fork failed"
                          : WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status)) : "ended by a signal")
            << "); running in one process instead (--ranks 1 skips the attempt)\n";
}

}  // namespace vrsph::cli
