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
  check<ConfigError>(o.min_growth > 1 && o.min_growth <= o.max_growth && std::isfinite(o.max_growth),
                     "the sweep's growth bounds must satisfy 1 < min <= max, got ", o.min_growth, " and ", o.max_growth);
  check<ConfigError>(o.max_bytes >= 0 && o.max_seconds >= 0, "the sweep's limits must be >= 0");
}

// Order in n of the last two runs, or NaN when they do not give one (equal n, no gain).
double last_order(const std::vector<SweepRun>& runs) {
  if (runs.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const SweepRun& a = runs[runs.size() - 2];
  const SweepRun& b = runs.back();
  if (b.n <= a.n || !(a.error > 0) || !(b.error > 0)) return std::numeric_limits<double>::quiet_NaN();
  return std::log(a.error / b.error) / std::log(static_cast<double>(b.n) / a.n);
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
    for (SweepTarget& t : result.targets)
      if (!t.reached && r.error <= t.target) {
        t.reached = true;
        t.run = r;
      }
    if (pending() == 0) break;
    // Next: the resolution the largest target left needs at the observed order.
    double next_target = 0;
    for (const SweepTarget& t : result.targets)
      if (!t.reached) next_target = std::max(next_target, t.target);
    const double order = last_order(result.runs);
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
    const double p = std::isfinite(order) && order >= 0.5 ? std::min(order, 8.0) : options.nominal_order;
    const double wanted = n * std::pow(r.error / next_target, 1 / p) * options.margin;
    // Before two runs give an order the step is a probe of at most 1.5: a nominal order
    // too low for the configuration would jump far past its target.
    const double max_growth = result.runs.size() < 2 ? std::min(1.5, options.max_growth) : options.max_growth;
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
                             short_number(options.max_seconds),
                             " s per run"));
      break;
    }
    n = next;
  }
  return result;
}

}  // namespace vrsph
