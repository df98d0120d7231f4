// SPDX-License-Identifier: BSD-3-Clause
#include "relaunch.hpp"

#include <unistd.h>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>
#include <vrsph/core/error.hpp>
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
#ifdef _OPENMP
  const int cores = omp_get_num_procs();
#else
  const int cores = 1;
#endif
  check<ConfigError>(ranks <= cores, "--ranks ", ranks, " is more than this machine's ", cores,
                     " cores (run mpirun yourself to oversubscribe or to use several machines)");
  check<ConfigError>(std::system("command -v mpirun >/dev/null 2>&1") == 0,
                     "--ranks needs mpirun (Debian's openmpi-bin), which is not on PATH");
  std::error_code ec;
  const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  check<IoError>(!ec && !self.empty(), "--ranks: cannot find this program's path (/proc/self/exe)");
  std::vector<std::string> args = {"mpirun"};
  if (::geteuid() == 0) args.emplace_back("--allow-run-as-root");
  args.insert(args.end(), {"-np", std::to_string(ranks), self});
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--ranks") {
      ++k;  // and its value
      continue;
    }
    if (a.rfind("--ranks=", 0) == 0) continue;
    args.push_back(a);
  }
  std::vector<char*> c_args;
  for (auto& a : args) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  ::execvp("mpirun", c_args.data());
  throw IoError(detail::concat("--ranks: could not start mpirun: ", std::strerror(errno)));
}

}  // namespace vrsph::cli
