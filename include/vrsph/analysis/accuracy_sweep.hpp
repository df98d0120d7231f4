// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Time to accuracy: for a list of target errors, the smallest problem of one configuration
// (a method, a finite element degree, ...) that reaches each, found by a short refinement
// sweep that predicts the next size from the observed order of convergence, and refuses a
// size whose predicted memory or time is over a limit instead of running out of either.
// The configuration is a function n -> run; the sweep knows nothing of methods or peers
// (`vrsph bench accuracy` runs vrsph's rows and the FEniCSx peer through it).
#include <functional>
#include <string>
#include <vector>

namespace vrsph {

/// One solve of the sweep at resolution n (intervals per direction).
struct SweepRun {
  int n = 0;
  double unknowns = 0;    ///< problem size reported (particles, nodes)
  double seconds = 0;     ///< wall time to the solution
  double error = 0;       ///< max-norm error
  double peak_bytes = 0;  ///< memory the run used (0: unknown)
  int iterations = 0;
};

struct SweepOptions {
  std::vector<double> targets;  ///< target errors (> 0, any order)
  int dim = 2;                  ///< unknowns grow as n^dim (predictions)
  int n_start = 8;
  double nominal_order = 2;     ///< order in n assumed before two runs give one
  /// The predicted n for the next target is multiplied by this: a prediction just short of
  /// the target costs a whole extra run, one just beyond it a few per cent of time.
  double margin = 1.05;
  /// Bounds on n_next / n (max_growth 0: 16^(1/dim), at most 16 times the unknowns); before
  /// two runs have given an order, at most 1.5 (a probe). The order is fitted to the last
  /// three runs (errors on disordered clouds scatter).
  double min_growth = 1.15, max_growth = 0;
  /// After the sweep, for each target: runs at the geometric middle between the largest run
  /// that missed it and the smallest that reached it, while that one's error is below
  /// refine_below times the target and the two differ by more than refine_ratio in n, at most
  /// refine_runs times (0: no refinement). A step predicted from a scattered order can land
  /// far past a target, and a run well inside it may be a size too large: in 3D a factor 1.2
  /// in n is 1.7 in unknowns and more in time, so the races' time ratios need the finer
  /// bracket (each configuration gets the same).
  double refine_ratio = 1.1;
  double refine_below = 0.9;
  int refine_runs = 4;
  double max_bytes = 0;    ///< memory limit of one run (0: none)
  double max_seconds = 0;  ///< time limit of one run (0: none)
  int max_n = 1 << 20;
  /// The resolutions the configuration can take (e.g. multiples of a degree): n -> the
  /// smallest admissible n' >= n. Default: n itself.
  std::function<int(int)> admissible;
};

/// A target and the first (smallest) run of the sweep that reached it.
struct SweepTarget {
  double target = 0;
  bool reached = false;
  SweepRun run;        ///< reached: the run (no time is ever given for a run that missed)
  std::string reason;  ///< not reached: why (limit, stall, error of the run)
};

struct SweepResult {
  std::vector<SweepRun> runs;        ///< in the order run (n increasing)
  std::vector<SweepTarget> targets;  ///< in the order given
};

/// Runs `run` at increasing n until every target is reached (then refines, see
/// refine_ratio; a target's run is the smallest n that reached it), the error stops decreasing
/// (two runs in a row gain less than a factor 1.1: the solver's tolerance or round-off), or
/// the next size would exceed a limit (predicted from the runs so far: memory affine in the
/// unknowns, time as unknowns^1.1). An exception of `run` ends the sweep and becomes the
/// reason of the targets left (vrsph::Interrupted is rethrown). Throws ConfigError for bad
/// options (no targets, a target <= 0 or not finite, n_start < 1, margin < 1, growth bounds
/// not 1 < min <= max (max 0: by dimension), refine_runs < 0).
SweepResult sweep_to_targets(const SweepOptions& options, const std::function<SweepRun(int n)>& run);

}  // namespace vrsph
