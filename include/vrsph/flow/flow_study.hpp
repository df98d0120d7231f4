// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The convergence studies of the flow layer (docs/flow.md), as the CLI (`vrsph flow`), the
// Python module and the tests run them:
//  - the frozen-cloud projection: u* = u_exact + ∇φ on a periodic cloud, projected once; the
//    projection should return u_exact and remove ∇φ;
//  - the periodic vortices (Taylor–Green in 2D, Beltrami in 3D) run to a time, with the error
//    measures of the ISPH literature beside max-norm errors.
#include <cstdint>
#include <functional>
#include <vrsph/flow/exact_flows.hpp>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph {

struct FlowCloudSpec {
  int dim = 2;
  int nx = 32;            ///< particles per unit period along each axis (dx = 1 / nx)
  Real jitter = 0.2;      ///< displacement U(-jitter dx, jitter dx) per coordinate (0: a lattice)
  std::uint64_t seed = 1;
};
/// The periodic unit box [0,1)^d with nx^d particles (lattice, jittered). ConfigError for bad settings.
PointCloud periodic_flow_cloud(const FlowCloudSpec& spec);

struct ProjectionStudyRow {
  int nx = 0;
  Index particles = 0;
  Real error_u_inf = 0;      ///< max_i |u_i - u_exact,i| / max |u_exact|
  Real error_u_l2 = 0;       ///< rms |u - u_exact| / rms |u_exact|
  Real error_gradp_inf = 0;  ///< max |G φ_h - ∇φ| / max |∇φ| (the same vectors as error_u, scaled by ∇φ)
  Real error_phi_inf = 0;    ///< max |φ_h - φ| (both with zero mean) / max |φ|
  Real max_div_before = 0;   ///< max |D u*|
  Real max_div_after = 0;    ///< max |D u|
  Real shift = 0;            ///< the projection's λ
  int iterations = 0;
  double seconds = 0;        ///< operators + factorisation + projection
};
/// One frozen-cloud projection with these operators: u_exact the vortex at t = 0, φ = sin 2πx cos 4πy / 2π
/// (3D: × cos 2πz).
ProjectionStudyRow frozen_projection(const FlowCloudSpec& cloud, const OperatorsOptions& operators,
                                     const SolverOptions& solver);

/// The error measures of a periodic vortex at time t, at the particles' positions.
struct VortexErrors {
  Real error_u_mean = 0;      ///< mean_i |u_i - u(x_i)| / mean_i |u(x_i)|
  Real error_u_inf = 0;       ///< max_i |u_i - u(x_i)| / max |u|(t)
  Real error_p_mean = 0;      ///< mean_i |p_i - p(x_i)| (each with its mean removed) / max |p|(t)
  Real error_p_inf = 0;       ///< max_i of the same / max |p|(t)
  Real decay_rate_error = 0;  ///< |max_i |u_i| - max |u|(t)| / max |u|(t)
};
VortexErrors vortex_errors(const PeriodicVortex& vortex, const std::vector<Vec3>& x, const Eigen::MatrixXd& u,
                           const Field& p, Real t);

struct VortexRunOptions {
  FlowCloudSpec cloud;
  PeriodicVortex vortex;  ///< its dim is the cloud's; the flow's ν is set from its Re
  FlowOptions flow;
  Real t_end = 1;
  /// dt = cfl dx / U (rounded to hit t_end), shortened at the steps where 0.9 of the stability
  /// limit asks for less (it moves with the velocity and, Lagrangian, with the particles).
  Real cfl = 0.25;
  /// > 0: this fixed time step instead (t_end rounded to whole steps; a step beyond the stability
  /// limit is refused, or warned about with FlowOptions::allow_unstable).
  Real dt = 0;
  /// Called after every step (progress, VTU output); may be empty.
  std::function<void(const FlowSolver&)> on_step;
};

struct VortexRunRow {
  int nx = 0;
  Index particles = 0;
  Real t = 0, dt = 0;  ///< dt: the smallest step taken
  Index steps = 0;
  VortexErrors errors;
  Real max_div_u = 0;
  Real kinetic_energy = 0;
  Real min_spacing = 0, max_spacing = 0;  ///< over the whole run (nearest-neighbour distance / dx)
  Real min_support_isotropy = 1;  ///< the smallest FlowStepReport::min_support_isotropy of the run
  Real max_support_growth = 1;    ///< the largest FlowStepReport::max_support_growth of the run
  double ppe_iterations_per_step = 0;
  double seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;  ///< the last three per step
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
  bool warm_start = true;        ///< the volumes' start used (FlowOptions::warm_start resolved)
  Real support_growth = 1;       ///< the supports' growth cap used (FlowOptions::support_growth resolved)
};
/// A vortex run from its exact velocity at t = 0. Throws as FlowSolver.
VortexRunRow run_periodic_vortex(const VortexRunOptions& options);

}  // namespace vrsph
