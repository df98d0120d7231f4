// SPDX-License-Identifier: BSD-3-Clause
// `vrsph bench solve`: Example 5 from nothing to the solution, stage by stage, for a
// list of sizes and solvers in one run; optionally the FEniCSx Pk + BoomerAMG peer
// (../shared/anchors/fenicsx_ex5.py, fenicsx_anchor.hpp) on about the same numbers of
// unknowns, in the same run and on the same cores, with ratios.
#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <memory>
#include <string>
#include <vector>
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/bvp_study.hpp>
#include <vrsph/analysis/convergence.hpp>
#include <vrsph/core/error.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#include "bench_run.hpp"
#include "../relaunch.hpp"
#include "fenicsx_anchor.hpp"
#include "study_args.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vrsph::cli {

namespace {
struct SolveBenchArgs {
  int dim = 2, threads = 0;
  std::string n = "100,200,400", method = "vrsph", cloud = "perturbed", solvers = "petsc", petsc_options;
  AnchorOptions peer;
  std::vector<std::string> method_opts;
  std::uint64_t seed = 1;
  double h_factor = 3;
  bool baseline = false;
  OutputOptions out;
};

// Stage seconds of one run, for the efficiency against a one-rank baseline.
struct StageTimes {
  double build = 0, solve = 0, total = 0;  // build: neighbours + stencils + assembly
};
StageTimes stage_times(const BvpRun& r) {
  // The partition's time is part of the neighbour stage (BvpSolution::seconds_neighbours).
  return {r.seconds_neighbours + r.seconds_stencil + r.seconds_assemble, r.seconds_solve, run_seconds_total(r)};
}

}  // namespace

namespace {
// The study behind the benchmark: [QW] Example 5 on the requested cloud, memory measured.
BvpStudyParams bench_params(const SolveBenchArgs& a, const Communicator& comm) {
  check<ConfigError>(a.dim == 2 || a.dim == 3, "--dim must be 2 or 3 for bench solve, got ", a.dim);
  check<ConfigError>(a.peer.anchor.empty() || a.peer.anchor == "fenicsx", "--anchor must be fenicsx, got '", a.peer.anchor, "'");
  check<ConfigError>(!a.baseline || comm.distributed(), "--baseline compares with one rank: run under mpirun with "
                     "more than one rank");
  BvpStudyParams p = example5_bench_params("bench solve", a.dim, a.cloud, a.h_factor, a.method, a.method_opts);
  p.communicator = comm;
  return p;
}

// The peer's rows of one size, one per degree.
using AnchorRows = std::vector<AnchorRun>;

// The peer on every size and degree, launched by rank 0 (serial or under its own mpirun)
// while our other ranks sleep; only rank 0 prints. A failure of the peer is rank 0's;
// after the (sleeping) barrier every rank throws it.
std::vector<AnchorRows> run_anchors(const SolveBenchArgs& a, const BvpStudyParams& p, const std::vector<int>& sizes,
                                    const Communicator& comm) {
  std::vector<AnchorRows> anchor;
  if (a.peer.anchor.empty()) return anchor;
  const std::vector<int> degrees = parse_anchor_degrees(a.peer.degrees);
  const AnchorSetup setup = anchor_setup(a.peer, a.dim);
  const bool perturbed = p.cloud == CloudFamily::Perturbed;
  Progress progress;
  std::exception_ptr failure;
  try {
    if (comm.is_root()) warm_up_anchor(setup, degrees);
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      progress.update("anchor n=" + std::to_string(sizes[k]), static_cast<double>(k) / static_cast<double>(sizes.size()));
      AnchorRows rows(degrees.size());
      if (comm.is_root()) {
        const TemporaryFile points("vrsph-anchor-cloud", ".csv");
        bool written = false;
        for (std::size_t d = 0; d < degrees.size(); ++d) {
          const AnchorMesh mesh = anchor_mesh(setup, perturbed, degrees[d]);
          if (mesh == AnchorMesh::SamePoints && !written) {
            write_bench_cloud(p, sizes[k], a.seed, points.path());
            written = true;
          }
          rows[d] = run_anchor(setup, degrees[d], anchor_cells(sizes[k], degrees[d]), mesh, points.path());
        }
      }
      anchor.push_back(std::move(rows));
    }
  } catch (...) {
    failure = std::current_exception();
  }
  idle_barrier(comm);
  collective(comm, [&] {
    if (failure) std::rethrow_exception(failure);
  });
  return anchor;
}

std::vector<std::string> bench_columns(bool baseline, const std::vector<int>& anchor_degrees) {
  std::vector<std::string> c = {"n", "N", "method", "solver", "seconds_cloud", "seconds_data", "seconds_neighbours",
                                "seconds_stencil", "seconds_assemble", "seconds_setup", "seconds_solve", "seconds_total",
                                "solver_iterations", "error_inf", "bytes_per_particle", "bytes_per_particle_cloud",
                                "bytes_per_particle_neighbours", "bytes_per_particle_stencil",
                                "bytes_per_particle_assemble", "bytes_per_particle_solve", "ranks", "seconds_partition",
                                "halo_bytes", "halo_bytes_max", "halo_messages", "halo_particles", "owned_particles",
                                "peak_memory_mib_per_rank"};
  if (baseline)
    c.insert(c.end(), {"baseline_seconds_build", "baseline_seconds_solve", "baseline_seconds_total",
                       "parallel_efficiency_build", "parallel_efficiency_solve", "parallel_efficiency"});
  // anchor_*: the first degree listed (the P1 columns of the single-peer benchmark).
  if (!anchor_degrees.empty())
    c.insert(c.end(), {"anchor_seconds_total", "anchor_iterations", "anchor_error_inf", "ratio_to_anchor"});
  for (int k : anchor_degrees)
    for (const char* what : {"cells", "nodes", "mesh", "seconds_total", "iterations", "error_inf", "peak_memory_mib"})
      c.push_back("anchor_p" + std::to_string(k) + "_" + what);
  for (int k : anchor_degrees) c.push_back("ratio_to_anchor_p" + std::to_string(k));
  return c;
}

// One run's row: stage seconds, memory per particle above what the process held before the
// run (program, libraries), the partition's figures.
std::vector<std::pair<std::string, TableCell>> bench_row(const BvpRun& r, int n, const std::string& method,
                                                        const Communicator& comm) {
  const double total = stage_times(r).total;
  const auto per = [&](std::size_t bytes) {
    return run_bytes_above_start(r, bytes) / static_cast<double>(comm.distributed() ? r.distribution.owned : r.particles);
  };
  const auto& sp = r.stage_peak_bytes;
  const std::size_t peak = run_peak_bytes(r);
  return {{"n", static_cast<long long>(n)},
          {"N", static_cast<long long>(r.particles)},
          {"method", method},
          {"solver", r.solve.solver},
          {"seconds_cloud", r.seconds_cloud},
          {"seconds_data", r.seconds_data},
          {"seconds_neighbours", r.seconds_neighbours},
          {"seconds_stencil", r.seconds_stencil},
          {"seconds_assemble", r.seconds_assemble},
          {"seconds_setup", r.solve.seconds_setup},
          {"seconds_solve", r.seconds_solve},  // set-up included, as in the study rows
          {"seconds_total", total},
          {"solver_iterations", static_cast<long long>(r.solve.iterations)},
          {"error_inf", r.errors.all.linf},
          {"bytes_per_particle", per(peak)},
          {"bytes_per_particle_cloud", per(r.peak_bytes_cloud)},
          {"bytes_per_particle_neighbours", per(sp.neighbours)},
          {"bytes_per_particle_stencil", per(sp.stencil)},
          {"bytes_per_particle_assemble", per(sp.assemble)},
          {"bytes_per_particle_solve", per(sp.solve)},
          {"ranks", static_cast<long long>(comm.size())},
          {"seconds_partition", r.distribution.seconds_distribute},
          {"halo_bytes", static_cast<long long>(r.distribution.halo_bytes_total)},  // all ranks, one exchange
          {"halo_bytes_max", static_cast<long long>(r.distribution.halo_bytes_max)},
          {"halo_messages", static_cast<long long>(r.distribution.halo_messages)},
          {"halo_particles", static_cast<long long>(r.distribution.halo)},
          {"owned_particles", static_cast<long long>(comm.distributed() ? r.distribution.owned : r.particles)},
          {"peak_memory_mib_per_rank", r.peak_memory_mib}};
}

// Every size with one solver: the rows, and the cost slopes in N into `meta`.
void bench_solver(const SolveBenchArgs& a, BvpStudyParams& p, const std::vector<int>& sizes,
                  const std::vector<AnchorRows>& anchor, const std::string& solver, Table& t, Progress& progress,
                  double& done, double total_runs, Json& meta) {
  const Communicator& comm = p.communicator;
  std::vector<Real> big_n, work, iterations;
  std::vector<std::string> warnings;  // the runs' (e.g. a PETSc option no object used), once each at the end
  warm_up_run(p, a.method, a.seed);
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    progress.update(solver + " n=" + std::to_string(sizes[k]), done++ / total_runs);
    // The one-rank baseline first, rank 0 alone, with the other ranks asleep.
    StageTimes base;
    if (a.baseline) {
      if (comm.is_root()) {
        BvpStudyParams serial = p;
        serial.communicator = Communicator();
        base = stage_times(run_bvp(serial, a.method, sizes[k], a.seed, false, nullptr, nullptr));
      }
      idle_barrier(comm);
    }
    const BvpRun r = run_bvp(p, a.method, sizes[k], a.seed, false, &warnings, nullptr);
    const StageTimes times = stage_times(r);
    auto row = bench_row(r, sizes[k], a.method, comm);
    if (a.baseline) {
      const double P = comm.size();
      row.emplace_back("baseline_seconds_build", base.build);
      row.emplace_back("baseline_seconds_solve", base.solve);
      row.emplace_back("baseline_seconds_total", base.total);
      row.emplace_back("parallel_efficiency_build", base.build / (P * times.build));
      row.emplace_back("parallel_efficiency_solve", base.solve / (P * times.solve));
      row.emplace_back("parallel_efficiency", base.total / (P * times.total));
    }
    if (!anchor.empty() && comm.is_root()) {
      const AnchorRun& first = anchor[k].front();
      row.emplace_back("anchor_seconds_total", first.seconds_total);
      row.emplace_back("anchor_iterations", static_cast<long long>(first.iterations));
      row.emplace_back("anchor_error_inf", first.error_inf);
      row.emplace_back("ratio_to_anchor", times.total / first.seconds_total);
      for (const AnchorRun& run : anchor[k]) {
        const std::string pk = "anchor_p" + std::to_string(run.degree) + "_";
        row.emplace_back(pk + "cells", static_cast<long long>(run.cells));
        row.emplace_back(pk + "nodes", run.nodes);
        row.emplace_back(pk + "mesh", to_string(run.mesh));
        row.emplace_back(pk + "seconds_total", run.seconds_total);
        row.emplace_back(pk + "iterations", static_cast<long long>(run.iterations));
        row.emplace_back(pk + "error_inf", run.error_inf);
        row.emplace_back(pk + "peak_memory_mib", run.peak_bytes / (1024.0 * 1024.0));
        row.emplace_back("ratio_to_anchor_p" + std::to_string(run.degree), times.total / run.seconds_total);
      }
    }
    t.add_row(row);
    big_n.push_back(static_cast<Real>(r.particles));
    work.push_back(r.seconds_assemble + r.seconds_solve);
    iterations.push_back(std::max(1, r.solve.iterations));
  }
  if (comm.is_root()) print_warnings(warnings, false);
  // Cost slopes in N: least_squares_order fits log(value) against log(1/size).
  if (sizes.size() < 2) return;
  std::vector<Real> inverse;
  for (Real v : big_n) inverse.push_back(1 / v);
  meta["slope_assemble_solve"][solver] = -least_squares_order(inverse, work);
  meta["slope_iterations"][solver] = -least_squares_order(inverse, iterations);
}

void run_solve_bench(const SolveBenchArgs& a, bool threads_given) {
  validate_output(a.out);
  const std::vector<int> sizes = parse_int_list(a.n, "--n");
  const std::vector<std::string> solvers = parse_name_list(a.solvers, "--solver");
  // --ranks auto: a large benchmark of PETSc solves on one rank per core, as study and solve
  // run; not when the threads were given (they are what is measured) nor beside the peer
  // (which starts its own mpirun).
  if (!threads_given && a.peer.anchor.empty() && (a.dim == 2 || a.dim == 3) &&
      std::all_of(solvers.begin(), solvers.end(), [](const std::string& s) { return s == "petsc"; })) {
    const int largest = sizes.empty() ? 0 : *std::max_element(sizes.begin(), sizes.end());
    run_on_ranks_if_large(static_cast<Index>(std::pow(largest + 1.0, a.dim)), a.dim, true);
  }
  set_thread_count(a.threads);
  const Communicator& comm = communicator();
  BvpStudyParams p = bench_params(a, comm);
  std::vector<SolverOptions> solver_options;
  for (const auto& s : solvers) {
    SolverOptions o;
    o.type = parse_solver(s);
    o.petsc_options = a.petsc_options;
    solver_options.push_back(o);
  }
  const std::vector<AnchorRows> anchor = run_anchors(a, p, sizes, comm);
  Table t;
  t.columns = bench_columns(a.baseline, a.peer.anchor.empty() ? std::vector<int>{} : parse_anchor_degrees(a.peer.degrees));
  Json meta;
  meta["benchmark"] = "solve";
  meta["dim"] = a.dim;
  meta["cloud"] = a.cloud;
  meta["method"] = a.method;
  meta["method_options"] = a.method_opts;
#ifdef _OPENMP
  meta["threads"] = omp_get_max_threads();
#else
  meta["threads"] = 1;
#endif
  Progress progress;
  const double total_runs = static_cast<double>(sizes.size() * solvers.size());
  double done = 0;
  for (std::size_t s = 0; s < solvers.size(); ++s) {
    p.solver = solver_options[s];
    p.solver.dimension = a.dim;
    bench_solver(a, p, sizes, anchor, solvers[s], t, progress, done, total_runs, meta);
  }
  meta["peak_memory_mib"] = max_over_ranks(comm, peak_memory_mib());
  meta["ranks"] = comm.size();
  emit(t, a.out, meta, "N", "seconds_total:1,solver_iterations:0", "solver",
       "Example 5 " + std::to_string(a.dim) + "D " + a.cloud + ": seconds and solver iterations to solution");
}
}  // namespace

void add_solve_bench(CLI::App& bench) {
  auto a = std::make_shared<SolveBenchArgs>();
  auto* cmd = bench.add_subcommand("solve", "[QW] Example 5 end to end: seconds and memory per stage, solver iterations, "
                                            "against the FEniCSx Pk + BoomerAMG peer (--anchor fenicsx --anchor-degree 1,2,3)");
  cmd->add_option("--dim", a->dim, "Dimension 2 or 3")->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction, comma-separated ((n+1)^d particles)")->capture_default_str();
  cmd->add_option("--method", a->method, "Method (see `vrsph methods`)")->capture_default_str();
  cmd->add_option("--cloud", a->cloud, "uniform or perturbed")->capture_default_str();
  cmd->add_option("--solver", a->solvers, "Comma-separated solvers: petsc, auto, umfpack, sparselu, bicgstab")
      ->capture_default_str();
  cmd->add_option("--petsc-options", a->petsc_options, "PETSc options (after the defaults and PETSC_OPTIONS)");
  cmd->add_option("--method-opt", a->method_opts, "Method option key=value, or method:key=value (repeatable)");
  cmd->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius h = h_factor * dx")->capture_default_str();
  add_anchor_options(*cmd, a->peer,
                     "Run a peer in the same run on the same cores: fenicsx (Lagrange Pk, CG + BoomerAMG), about the "
                     "same unknowns as each size (round(n/k) cells); on a 2D perturbed cloud with one peer rank P1 "
                     "solves on our very points and P2, P3 on the peer's own perturbed nodes; on more ranks and in 3D "
                     "the peer meshes its lattice (it cannot mesh points in parallel)");
  cmd->add_flag("--baseline", a->baseline,
                "Under mpirun: also run each size on rank 0 alone (the others sleep) and report the parallel "
                "efficiency T_1 / (P T_P) of the build (neighbours, stencils, assembly, partition), of the solve and "
                "of the whole");
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->add_option("--plot", a->out.plot, "Also plot seconds_total and solver_iterations against N (log-log, reference slopes 1 and 0) into this PNG file");
  cmd->callback([a, cmd] {
    reject_peer_options_without_peer(*cmd, a->peer);
    run_solve_bench(*a, cmd->count("--threads") > 0);
  });
}

}  // namespace vrsph::cli
