// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The time steps of the flow studies (run_periodic_vortex, run_cavity): a fixed one, or the target
// shortened to 0.9 of the stability limit, which moves with the velocity (and, Lagrangian, the
// particles); the last step ends at t_end. A run of more than 1e7 steps would take days: it is
// refused before it starts, and stopped if the stability limit shortens the steps that far. A
// limit that collapses means the velocity grew without bound: NumericalError naming the step.
#include <algorithm>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph::detail {

constexpr Real kMaxStudySteps = 1e7;

/// ConfigError ("<what>: t_end ... would take ... steps") for a run of over 1e7 steps of dt.
inline void check_study_length(const char* what, Real t_end, Real dt) {
  check<ConfigError>(t_end / dt <= kMaxStudySteps, what, ": t_end ", t_end, " at a step of ", dt, " would take ",
                     t_end / dt, " steps (at most 1e7)");
}

/// Whether step `steps` + 1 of `dt` has collapsed to 1e-6 of `reference` (a velocity that grew
/// without bound shortens the stable step towards zero); if so, `why` says so, naming the step,
/// the time and the speed, and `hint` what to try.
inline bool step_collapsed(const FlowSolver& solver, Index steps, Real dt, Real reference, const std::string& hint,
                           std::string& why) {
  if (dt > 1e-6 * reference) return false;
  why = concat("flow step ", steps + 1, " (t = ", solver.time(), "): the stable time step fell to ", dt, " (max |u| = ",
               solver.last().max_speed, "): the run is unstable (", hint, ")");
  return true;
}

/// The next step after `steps` of them (the smallest so far `smallest`), `hint` what to try when
/// the stability limit collapses.
inline Real next_study_step(const FlowSolver& solver, const char* what, Real fixed_dt, Real target, Real t_end,
                            Index steps, Real smallest, const std::string& hint) {
  check<NumericalError>(static_cast<Real>(steps) < kMaxStudySteps, what, ": 1e7 steps reached at t = ", solver.time(),
                        " of ", t_end, " (the stability limit shortened the steps to ", smallest, ")");
  Real dt = fixed_dt;
  if (dt <= 0) {
    dt = std::min(target, solver.stable_time_step(0.9));
    if (std::string why; step_collapsed(solver, steps, dt, target, hint, why)) throw NumericalError(why);
  }
  const Real left = t_end - solver.time();
  return dt >= left * (1 - 1e-9) ? left : dt;
}

/// The costs of a study's steps: PPE iterations and seconds per stage, summed, then per step.
struct StepCosts {
  double iterations = 0, update = 0, ppe = 0, rhs = 0, viscous = 0;
  Index steps = 0;
  void add(const FlowStepReport& r) {
    ++steps;
    iterations += r.ppe_iterations;
    update += r.seconds_update;
    ppe += r.seconds_ppe;
    rhs += r.seconds_rhs;
    viscous += r.seconds_viscous;
  }
  /// A study row's steps and per-step costs (its fields steps, seconds_per_step, seconds_update,
  /// seconds_ppe, seconds_rhs, seconds_viscous, ppe_iterations_per_step), `seconds` the wall time of the steps.
  template <class Row>
  void write(Row& row, double seconds) const {
    const auto n = static_cast<double>(std::max<Index>(steps, 1));
    row.steps = steps;
    row.seconds_per_step = seconds / n;
    row.seconds_update = update / n;
    row.seconds_ppe = ppe / n;
    row.seconds_rhs = rhs / n;
    row.seconds_viscous = viscous / n;
    row.ppe_iterations_per_step = iterations / n;
  }
};

}  // namespace vrsph::detail
