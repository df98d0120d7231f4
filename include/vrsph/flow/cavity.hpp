// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The lid-driven cavity (docs/flow.md): the unit square with walls at rest and a lid y = 1
// sliding at speed 1 along x, run from rest to a steady state — in the Eulerian frame on a
// fixed, disordered cloud, or in the Lagrangian one with the particles moving (shifting
// advised) — and its centre-line velocities against Ghia, Ghia & Shin (1982).
#include <cstdint>
#include <functional>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph {

struct CavityCloudSpec {
  int nx = 32;          ///< intervals per side (dx = 1 / nx): (nx + 1)² particles, 4 nx of them walls
  Real jitter = 0.2;    ///< fluid particles displaced by U(-jitter dx, jitter dx) per coordinate
  std::uint64_t seed = 1;
  /// Layers of wall particles: the faces, and wall_layers - 1 more outside the square, dx apart
  /// (the lid's slide with it). 0: one in the Eulerian frame, three in the Lagrangian one
  /// (run_cavity; cavity_cloud takes 0 as 1), where the walls' extrapolated pressure rows and
  /// least-squares gradient rows need a full support (one layer: the corner's gradient row
  /// became singular once the water moved, docs/flow.md).
  int wall_layers = 0;
};
/// The vertex lattice of [0,1]² with its faces as walls (tag Dirichlet, outward normals; at the
/// corners the diagonal), the extra wall layers outside it (their face's normal; the diagonal
/// beyond a corner), and the fluid particles jittered. ConfigError for bad settings.
PointCloud cavity_cloud(const CavityCloudSpec& spec);
/// The lid's velocity: (1, 0) on y >= 1 between the corners (the lid and its outer layers), 0
/// elsewhere (the corners are at rest).
Vec3 cavity_lid_velocity(const Vec3& x);

struct CavityRunOptions {
  CavityCloudSpec cloud;
  Real re = 100;           ///< Reynolds number of the lid (ν = 1 / Re)
  FlowOptions flow;        ///< nu and wall_velocity are set here
  Real t_end = 100;        ///< give up on a steady state at this time
  /// Steady when the velocity's rate of change falls below this: Eulerian, max |u^{n+1} - u^n| /
  /// dt over the fluid. Lagrangian (a particle's velocity changes along its path in a steady flow
  /// too, and a sample with the particles' arrangement): the centre lines are sampled every
  /// lagrangian_probe_interval of time, and the rate is the largest change at Ghia's points
  /// between the means of the last two windows of lagrangian_window samples over the time
  /// between them; the run is also steady when at every one of those points the two means
  /// differ by less than twice the standard error of their difference (steady within its
  /// fluctuations). The profiles reported are the last window's mean.
  Real steady_tolerance = 1e-4;
  Real lagrangian_probe_interval = 0.5;
  int lagrangian_window = 10;
  /// Lagrangian: FlowOptions::wall_gap unless `flow` sets one (< 0: none). The fluid next to the
  /// lid's upstream corner is sucked towards it (the pressure is singular there) and at Re = 1000
  /// or with SPH's rows a particle crossed the lid; at Re = 100 with VRSPH it never acts.
  Real lagrangian_wall_gap = 0.5;
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
  Real steady_residual = 0;       ///< the last rate of change (steady_tolerance says which)
  /// max_k |u(0.5, y_k) - u_Ghia,k| over the table's points strictly inside (the two ends are
  /// the walls' prescribed values), and likewise v(x_k, 0.5).
  Real ghia_max_deviation_u = 0, ghia_max_deviation_v = 0;
  /// The same against the converged P2–P1 solution at those points (ghia.hpp): the error of the
  /// run, where Ghia's table carries its own (5e-3 to 1.9e-2).
  Real reference_max_deviation_u = 0, reference_max_deviation_v = 0;
  std::vector<Real> u_at_ghia, v_at_ghia;  ///< the sampled values at the table's points (its order)
  Real max_div_u = 0;
  Real kinetic_energy = 0;
  /// Lagrangian: the time the reported profiles are averaged over (0: the last state's), and the
  /// largest standard deviation of the samples at Ghia's points about that mean.
  Real average_time = 0, profile_fluctuation = 0;
  Index wall_pushes = 0;  ///< particles the wall gap reflected over the run (FlowStepReport::wall_pushes)
  double ppe_iterations_per_step = 0;
  double seconds_setup = 0;       ///< operators, factorisation, the first projection
  double seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;  ///< the last three per step
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
  /// Centre-line profiles on 101 evenly spaced points: u(0.5, s_k) and v(s_k, 0.5), s_k = k / 100.
  std::vector<Real> line, u_line, v_line;
};
/// Runs the cavity from rest until it is steady or t_end. Throws as FlowSolver; ConfigError for
/// a Reynolds number Ghia et al. did not tabulate (100, 1000), bad settings.
CavityRunRow run_cavity(const CavityRunOptions& options);

}  // namespace vrsph
