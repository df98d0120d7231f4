// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The time step of the flow studies (run_periodic_vortex, run_cavity): a fixed one, or the target
// shortened to 0.9 of the stability limit, which moves with the velocity (and, Lagrangian, the
// particles). A limit that collapses means the velocity grew without bound: NumericalError naming
// the step, with `hint` (what to try).
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph::detail {

inline Real study_time_step(const FlowSolver& solver, Real fixed_dt, Real target, Index next_step, const std::string& hint) {
  if (fixed_dt > 0) return fixed_dt;
  const Real dt = std::min(target, solver.stable_time_step(0.9));
  check<NumericalError>(dt > 1e-6 * target, "flow step ", next_step, " (t = ", solver.time(), "): the stable time step "
                        "fell to ", dt, " (max |u| = ", solver.last().max_speed, "): the run is unstable (", hint, ")");
  return dt;
}

}  // namespace vrsph::detail
