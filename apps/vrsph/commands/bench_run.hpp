// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the solve benchmarks read off one BvpRun: its wall time from nothing to the solution
// and the memory it used. Shared by `bench solve` and `bench accuracy`, so both time the
// same stages.
#include <algorithm>
#include <vrsph/analysis/bvp_study.hpp>

namespace vrsph::cli {

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
