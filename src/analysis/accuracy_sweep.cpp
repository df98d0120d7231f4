// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/analysis/accuracy_sweep.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>

namespace vrsph {

namespace {
void check_sweep_options(const SweepOptions& o) {
  check<ConfigError>(!o.targets.empty(), "an accuracy sweep needs at least one target error");
  for (double t : o.targets)
    check<ConfigError>(std::isfinite(t) && t > 0, "a target error must be a positive number, got ", t);
  check<ConfigError>(o.dim >= 1 && o.dim <= 3, "the sweep's dimension must be 1, 2 or 3, got ", o.dim);
  check<ConfigError>(o.n_start >= 1 && o.n_start <= o.max_n, "the sweep's first n must be in [1, ", o.max_n, "], got ",
                     o.n_start);
  check<ConfigError>(std::isfinite(o.nominal_order) && o.nominal_order > 0, "the sweep's nominal order must be > 0");
  check<ConfigError>(std::isfinite(o.margin) && o.margin >= 1, "the sweep's margin must be >= 1, got ", o.margin);
  check<ConfigError>(o.min_growth > 1 && (o.max_growth == 0 || o.min_growth <= o.max_growth) && std::isfinite(o.max_growth),
                     "the sweep's growth bounds must satisfy 1 < min <= max (max 0: by dimension), got ", o.min_growth,
                     " and ", o.max_growth);
  check<ConfigError>(o.refine_runs >= 0 && std::isfinite(o.refine_ratio), "the sweep's refinement needs refine_runs >= 0");
  check<ConfigError>(o.refine_below > 0 && o.refine_below <= 1, "the sweep's refine_below must be in (0, 1], got ",
                     o.refine_below);
  check<ConfigError>(o.max_bytes >= 0 && o.max_seconds >= 0, "the sweep's limits must be >= 0");
}

// Order in n fitted (least squares in log-log) to the last three runs, or the last two:
// errors on disordered clouds scatter from run to run, and the order of one pair can be far
// from the trend (0.99 between two runs of a third-order method). NaN without two runs.
double recent_order(const std::vector<SweepRun>& runs) {
  const std::size_t k = std::min<std::size_t>(3, runs.size());
  if (k < 2) return std::numeric_limits<double>::quiet_NaN();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = runs.size() - k; i < runs.size(); ++i) {
    if (!(runs[i].error > 0)) return std::numeric_limits<double>::quiet_NaN();
    const double x = std::log(static_cast<double>(runs[i].n)), y = std::log(runs[i].error);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double kk = static_cast<double>(k), denom = kk * sxx - sx * sx;
  if (!(denom > 0)) return std::numeric_limits<double>::quiet_NaN();
  return -(kk * sxy - sx * sy) / denom;
}

// Memory of a run with `unknowns`, from the runs so far: affine through the last two where
// they grow, else proportional to the last (which overestimates: it scales the fixed part).
double predicted_bytes(const std::vector<SweepRun>& runs, double unknowns) {
  const SweepRun& b = runs.back();
  if (!(b.peak_bytes > 0) || !(b.unknowns > 0)) return 0;
  if (runs.size() >= 2) {
    const SweepRun& a = runs[runs.size() - 2];
    if (a.peak_bytes > 0 && b.unknowns > a.unknowns && b.peak_bytes > a.peak_bytes) {
      const double slope = (b.peak_bytes - a.peak_bytes) / (b.unknowns - a.unknowns);
      return b.peak_bytes + slope * (unknowns - b.unknowns);
    }
  }
  return b.peak_bytes * unknowns / b.unknowns;
}

double predicted_seconds(const SweepRun& last, double unknowns) {
  return last.seconds * std::pow(unknowns / std::max(1.0, last.unknowns), 1.1);
}

// 3 significant digits for messages (orders, seconds, errors).
std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

int admissible_n(const SweepOptions& o, int n) {
  const int m = o.admissible ? o.admissible(n) : n;
  check<ConfigError>(m >= n, "the sweep's admissible resolution of ", n, " is smaller (", m, ")");
  return m;
}
}  // namespace

namespace {
// Which runs reached which target: the smallest n among the runs at or below it.
void assign_runs(SweepResult& result) {
  for (SweepTarget& t : result.targets) {
    const SweepRun* best = nullptr;
    for (const SweepRun& r : result.runs)
      if (r.error <= t.target && (!best || r.n < best->n)) best = &r;
    t.reached = best != nullptr;
    if (best) {
      t.run = *best;
      t.reason.clear();
    }
  }
}

// Between the largest run that missed a target and the smallest that reached it with less
// than refine_below of the target's error: the geometric middle, while they are more than refine_ratio
// apart (a step predicted from a scattered order can land far past the target).
void bisect_targets(const SweepOptions& options, const std::function<SweepRun(int n)>& run, SweepResult& result) {
  if (!(options.refine_ratio > 1)) return;
  for (SweepTarget& t : result.targets)
    for (int k = 0; k < options.refine_runs; ++k) {
      assign_runs(result);
      if (!t.reached) break;
      const int hit = t.run.n;
      int miss = 0;
      for (const SweepRun& r : result.runs)
        if (r.n < hit && r.error > t.target) miss = std::max(miss, r.n);
      // Only where the run overshot: an error near the target says it is about the right size.
      if (miss == 0 || hit <= options.refine_ratio * miss || t.run.error > options.refine_below * t.target) break;
      const int mid = admissible_n(options, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(miss) * hit))));
      if (mid <= miss || mid >= hit ||
          std::any_of(result.runs.begin(), result.runs.end(), [&](const SweepRun& r) { return r.n == mid; }))
        break;
      try {
        SweepRun r = run(mid);
        r.n = mid;
        result.runs.push_back(r);
      } catch (const Interrupted&) {
        throw;
      } catch (const std::exception&) {
        break;  // the target stays reached by the larger run
      }
    }
  std::sort(result.runs.begin(), result.runs.end(), [](const SweepRun& a, const SweepRun& b) { return a.n < b.n; });
  assign_runs(result);
}
}  // namespace

SweepResult sweep_to_targets(const SweepOptions& options, const std::function<SweepRun(int n)>& run) {
  check_sweep_options(options);
  SweepResult result;
  for (double t : options.targets) result.targets.push_back({t, false, {}, {}});
  const auto pending = [&] {
    return std::count_if(result.targets.begin(), result.targets.end(), [](const SweepTarget& t) { return !t.reached; });
  };
  const auto give_up = [&](const std::string& reason) {
    for (SweepTarget& t : result.targets)
      if (!t.reached && t.reason.empty()) t.reason = reason;
  };
  int n = admissible_n(options, options.n_start);
  int stalls = 0;
  while (pending() > 0) {
    SweepRun r;
    try {
      r = run(n);
    } catch (const Interrupted&) {
      throw;
    } catch (const std::exception& e) {
      give_up(detail::concat("the run at n = ", n, " failed: ", e.what()));
      break;
    }
    r.n = n;
    result.runs.push_back(r);
    assign_runs(result);
    if (pending() == 0) break;
    // Next: the resolution the largest target left needs at the observed order.
    double next_target = 0;
    for (const SweepTarget& t : result.targets)
      if (!t.reached) next_target = std::max(next_target, t.target);
    if (result.runs.size() >= 2) {
      const double gain = result.runs[result.runs.size() - 2].error / r.error;
      stalls = gain < 1.1 ? stalls + 1 : 0;
      if (stalls >= 2) {
        give_up(detail::concat("stalled: the error stays near ", short_number(r.error), " from n = ",
                               result.runs[result.runs.size() - 3].n, " to n = ", n,
                               " (the solver's tolerance or round-off, not the resolution)"));
        break;
      }
    }
    const double order = recent_order(result.runs);
    const double p = std::isfinite(order) && order >= 0.5 ? std::min(order, 8.0) : options.nominal_order;
    const double wanted = n * std::pow(r.error / next_target, 1 / p) * options.margin;
    // At most 16 times the unknowns per step; before two runs give an order, a probe of at
    // most 1.5 in n: a nominal order too low for the configuration would jump far past its target.
    const double cap = options.max_growth > 0 ? options.max_growth : std::pow(16.0, 1.0 / options.dim);
    const double max_growth = result.runs.size() < 2 ? std::min(1.5, cap) : cap;
    const double growth = std::clamp(wanted / n, std::min(options.min_growth, max_growth), max_growth);
    const double next_real = std::ceil(n * growth);
    if (next_real > options.max_n) {
      give_up(detail::concat("not run: it needs about n = ", static_cast<long long>(std::ceil(wanted)),
                             " at the observed order ", short_number(p), ", beyond the sweep's largest n = ", options.max_n));
      break;
    }
    const int next = admissible_n(options, std::max(n + 1, static_cast<int>(next_real)));
    const double unknowns = r.unknowns * std::pow(static_cast<double>(next) / n, options.dim);
    const double bytes = predicted_bytes(result.runs, unknowns);
    if (options.max_bytes > 0 && bytes > options.max_bytes) {
      give_up(detail::concat("not run: the next size (n = ", next, ", about ", static_cast<long long>(unknowns),
                             " unknowns, about n = ", static_cast<long long>(std::ceil(wanted)),
                             " for the target at order ", short_number(p), ") would need about ", format_bytes(bytes),
                             ", over the memory limit of ", format_bytes(options.max_bytes)));
      break;
    }
    const double seconds = predicted_seconds(r, unknowns);
    if (options.max_seconds > 0 && seconds > options.max_seconds) {
      give_up(detail::concat("not run: the next size (n = ", next, ", about ", static_cast<long long>(unknowns),
                             " unknowns) would take about ", short_number(seconds), " s, over the limit of ",
                             short_number(options.max_seconds), " s per run"));
      break;
    }
    n = next;
  }
  bisect_targets(options, run, result);
  return result;
}

}  // namespace vrsph
