// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the solve benchmarks share: the study behind them ([QW] Example 5 on a uniform or
// perturbed lattice), its warm-up, the cloud file the peer triangulates, and what they read
// off one BvpRun (its wall time from nothing to the solution, the memory it used). Shared by
// `bench solve` and `bench accuracy`, so both set up and time the same runs.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>
#include <vrsph/analysis/bvp_study.hpp>

namespace vrsph::cli {

/// [QW] Example 5 in `dim` on a uniform or perturbed cloud (else a ConfigError naming
/// `command`), memory measured, the M-matrix check off (a diagnostic, not part of a user's
/// solve); `method` with its options checked before any run (ConfigError).
BvpStudyParams example5_bench_params(const std::string& command, int dim, const std::string& cloud, double h_factor,
                                     const std::string& method, const std::vector<std::string>& method_opts);
/// One tiny run (n = 8) first, so one-time costs (PETSc start-up, first page faults) stay out
/// of the timed runs, as the peer's imports and form compilation do. Its failure is not
/// reported (it would name a size nobody asked for; the first size asked for fails with its
/// own message if the cause is general); an interruption is.
void warm_up_run(const BvpStudyParams& p, const std::string& method, std::uint64_t seed);
/// The cloud of size n that run_bvp makes for `p`, as a CSV file for the peer's --points.
void write_bench_cloud(const BvpStudyParams& p, int n, std::uint64_t seed, const std::string& path);

/// Seconds from nothing to the solution: cloud, data, neighbours (with the partition),
/// stencils, assembly and solve (its set-up included).
inline double run_seconds_total(const BvpRun& r) {
  return r.seconds_cloud + r.seconds_data + r.seconds_neighbours + r.seconds_stencil + r.seconds_assemble +
         r.seconds_solve;
}

/// The highest resident memory of any stage (BvpStudyParams::measure_memory).
inline std::size_t run_peak_bytes(const BvpRun& r) {
  const auto& sp = r.stage_peak_bytes;
  return std::max({r.peak_bytes_cloud, sp.neighbours, sp.stencil, sp.assemble, sp.solve});
}

/// Resident bytes above what the process held when the run started (program, libraries).
inline double run_bytes_above_start(const BvpRun& r, std::size_t bytes) {
  return std::max(0.0, static_cast<double>(bytes) - static_cast<double>(r.resident_bytes_before));
}

}  // namespace vrsph::cli
