// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The lid-driven cavity (docs/flow.md): the unit square with walls at rest and a lid y = 1
// sliding at speed 1 along x, run from rest to a steady state in the Eulerian frame on a fixed,
// disordered cloud, and its centre-line velocities against Ghia, Ghia & Shin (1982).
#include <cstdint>
#include <functional>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph {

struct CavityCloudSpec {
  int nx = 32;          ///< intervals per side (dx = 1 / nx): (nx + 1)² particles, 4 nx of them walls
  Real jitter = 0.2;    ///< fluid particles displaced by U(-jitter dx, jitter dx) per coordinate
  std::uint64_t seed = 1;
};
/// The vertex lattice of [0,1]² with its faces as walls (tag Dirichlet, outward normals; at the
/// corners the diagonal) and the fluid particles jittered. ConfigError for bad settings.
PointCloud cavity_cloud(const CavityCloudSpec& spec);
/// The lid's velocity: (1, 0) on y = 1 between the corners, 0 elsewhere (the corners are at rest).
Vec3 cavity_lid_velocity(const Vec3& x);

struct CavityRunOptions {
  CavityCloudSpec cloud;
  Real re = 100;           ///< Reynolds number of the lid (ν = 1 / Re)
  FlowOptions flow;        ///< frame must be Eulerian; nu and wall_velocity are set here
  Real t_end = 100;        ///< give up on a steady state at this time
  /// Steady when max |u^{n+1} - u^n| / dt over the fluid falls below this.
  Real steady_tolerance = 1e-4;
  Real cfl = 0.25;         ///< dt = cfl dx (the lid's speed is 1), shortened to 0.9 of the stability limit
  Real dt = 0;             ///< > 0: this fixed step instead
  /// Called after every step with the solver and its steady residual; may be empty.
  std::function<void(const FlowSolver&, Real)> on_step;
};

struct CavityRunRow {
  int nx = 0;
  Index particles = 0;
  Real re = 0, t = 0, dt = 0;
  Index steps = 0;
  bool steady = false;
  Real steady_residual = 0;       ///< max |u^{n+1} - u^n| / dt of the last step
  /// max_k |u(0.5, y_k) - u_Ghia,k| over the table's points strictly inside (the two ends are
  /// the walls' prescribed values), and likewise v(x_k, 0.5).
  Real ghia_max_deviation_u = 0, ghia_max_deviation_v = 0;
  /// The same against the converged P2–P1 solution at those points (ghia.hpp): the error of the
  /// run, where Ghia's table carries its own (5e-3 to 1.9e-2).
  Real reference_max_deviation_u = 0, reference_max_deviation_v = 0;
  std::vector<Real> u_at_ghia, v_at_ghia;  ///< the sampled values at the table's points (its order)
  Real max_div_u = 0;
  Real kinetic_energy = 0;
  double ppe_iterations_per_step = 0;
  double seconds_setup = 0;       ///< operators, factorisation, the first projection
  double seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;  ///< the last three per step
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
  /// Centre-line profiles on 101 evenly spaced points: u(0.5, s_k) and v(s_k, 0.5), s_k = k / 100.
  std::vector<Real> line, u_line, v_line;
};
/// Runs the cavity from rest until it is steady or t_end. Throws as FlowSolver; ConfigError for
/// a Reynolds number Ghia et al. did not tabulate (100, 1000), a Lagrangian frame, bad settings.
CavityRunRow run_cavity(const CavityRunOptions& options);

}  // namespace vrsph
