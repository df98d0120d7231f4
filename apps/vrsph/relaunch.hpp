// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `vrsph --ranks P COMMAND ...`: the same command on P MPI ranks of this machine, started by
// vrsph itself under mpirun. The distributed pipeline then splits the work into P processes
// of one thread each; at 10^6 particles that beat one process with P threads by 17 % end to
// end on 2 cores, most of it in the solve (hypre runs one thread per process in Debian's
// build: docs/performance.md, "Threads or ranks").
#include <CLI/CLI.hpp>

namespace vrsph::cli {

/// Whether `app`'s command has a distributed pipeline (study, solve, diffuse, bench solve).
bool distributed_command(const CLI::App& app);

/// ranks == 1 (or already on that many ranks under mpirun): returns. Otherwise replaces this
/// process by `mpirun -np ranks <this program> <argv without --ranks>`, which does not
/// return. ConfigError: ranks < 1, more ranks than cores, a command without a distributed
/// pipeline, a different rank count under mpirun, mpirun not on PATH; IoError if the
/// launch itself fails.
void relaunch_on_ranks(int ranks, const CLI::App& app, int argc, char** argv);

}  // namespace vrsph::cli
