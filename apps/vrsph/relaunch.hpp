// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// `vrsph --ranks P COMMAND ...`: the same command on P MPI ranks of this machine, started by
// vrsph itself under mpirun. The distributed pipeline then splits the work into P processes
// of one thread each; at 10^6 particles that beat one process with P threads by 17 % end to
// end on 2 cores, most of it in the solve (hypre runs one thread per process in Debian's
// build: docs/performance.md, "Threads or ranks").
//
// `--ranks auto`, the default, does that for large runs only: the command decides once it
// knows its size (run_on_ranks_if_large), before any work.
#include <CLI/CLI.hpp>
#include <string>
#include <vrsph/core/types.hpp>

namespace vrsph::cli {

/// Whether `app`'s command has a distributed pipeline (study, solve, diffuse, bench solve).
bool distributed_command(const CLI::App& app);

/// ranks == 1 (or already on that many ranks under mpirun): returns. Otherwise replaces this
/// process by `mpirun -np ranks <this program> <argv without --ranks>`, which does not
/// return. ConfigError: ranks < 1, more ranks than cores, a command without a distributed
/// pipeline, a different rank count under mpirun, mpirun not on PATH; IoError if the
/// launch itself fails.
void relaunch_on_ranks(int ranks, const CLI::App& app, int argc, char** argv);

/// The value of --ranks: "auto" (then remembered with the command line for
/// run_on_ranks_if_large), or a whole number >= 1 passed to relaunch_on_ranks.
/// ConfigError for anything else.
void apply_ranks_option(const std::string& value, const CLI::App& app, int argc, char** argv);

/// The smallest run (particles) for which --ranks auto starts one rank per core, by dimension,
/// and the rank count it picks for `particles` in `dim` dimensions on `cores` cores (1: one
/// process). Measured on 2 cores, Example 5 perturbed, wall times with mpirun's start-up
/// (about 0.5-0.7 s) included (docs/time_to_accuracy.md, "Threads or ranks"): in 2D one rank
/// per core takes 0.91-0.93 x the time at 1.6 10^5 particles, 0.82-0.90 x at 3.0-4.9 10^5 and
/// 0.78-0.81 x at 10^6; in 3D, where the stencils are most of a run, 0.93 x at 2.3 10^5, 0.96-1.01
/// x at 3.1 10^5 and 0.87-0.90 x at 5.3 10^5 (since 3D solves coarsen aggressively, 0.87-1.19 x: break-even
/// on 2 cores; kept for machines with more cores, where one process's solve stays on one).
/// 1D runs are small and solved directly. The environment variable
/// VRSPH_RANKS_AUTO_MIN_PARTICLES sets one threshold for every dimension instead (where the
/// crossing lies depends on the machine).
inline constexpr Index kAutoRanksMinParticles2d = 150000;
inline constexpr Index kAutoRanksMinParticles3d = 200000;
inline constexpr const char* kAutoRanksMinParticlesVariable = "VRSPH_RANKS_AUTO_MIN_PARTICLES";
int large_run_ranks(Index particles, int dim, int cores, Index min_particles);
/// The threshold of `dim` dimensions: the environment's VRSPH_RANKS_AUTO_MIN_PARTICLES
/// (ConfigError unless a whole number >= 1), else the measured one above.
Index auto_ranks_min_particles(int dim);

/// With --ranks auto (the default): when this command's largest run has `particles`
/// particles in `dim` dimensions and is solved by PETSc (`petsc_solve`), and
/// large_run_ranks says more than one rank, runs this command again under mpirun on that
/// many ranks, waits for it and ends this process with its exit status (a note on stderr
/// says so first). Otherwise returns and the run goes on in this process: a small run; an
/// explicit --ranks; OMP_NUM_THREADS set (the user chose the threads); a build without MPI or
/// PETSc; no mpirun on PATH; already under mpirun; or mpirun that could not start the ranks
/// (then with a warning).
void run_on_ranks_if_large(Index particles, int dim, bool petsc_solve);

/// Under mpirun started by run_on_ranks_if_large: rank 0 tells the waiting parent that the
/// ranks started (called once the world is joined; nothing otherwise).
void mark_ranks_started();
/// Whether this run is on ranks that --ranks auto started (mark_ranks_started saw the parent):
/// its outputs are then those of one process (one .vtu file, plots), gathered on rank 0.
bool ranks_started_automatically();

}  // namespace vrsph::cli
