// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Water in a tank under gravity (docs/free_surface.md): the tank's cloud, and the hydrostatic
// tank — a column at rest with a free top, gravity ramped in — whose pressure must become
// ρ g (H - y) (unit density here: p = g (H - y)) while the particles stay at rest.
// The vertical is the last axis (y in 2D, z in 3D); gravity points down it.
#include <cstdint>
#include <functional>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph {

struct TankSpec {
  int dim = 2;
  int nx = 20;             ///< intervals across the tank's width (dx = width / nx)
  Real width = 1;          ///< the tank's width (every horizontal axis)
  Real depth = 1;          ///< H: the water's height (its top row of particles)
  Real column_width = 0;   ///< water in [0, column_width] along x only (a dam break); 0: the full width
  Real wall_height = 0;    ///< the walls' height; 0: depth + 4 dx
  int wall_layers = 1;     ///< layers of wall particles (the extra ones outside the box, at dx apart)
  Real jitter = 0;         ///< water particles displaced by U(-jitter dx, jitter dx) per coordinate (the top row only horizontally)
  std::uint64_t seed = 1;
};
/// The vertex lattice of the tank's box with its bottom and side faces as walls (tag Dirichlet,
/// outward normals, the diagonal at the corners), no lid, and the water's particles (Interior)
/// up to the depth (and across the column's width). Its domain is the tank's box, a depth taller
/// than the walls (room for the surface to rise; beyond it a particle is lost). ConfigError
/// for a column that does not fit the tank, a depth or width not a whole number of spacings
/// (within 1e-9), nx outside [4, 4096], a jitter outside [0, 0.5).
PointCloud tank_cloud(const TankSpec& spec);

struct HydrostaticRunOptions {
  TankSpec tank;           ///< its wall_height 0 here: walls up to the water's level
  FlowOptions flow;        ///< free_surface, body_force and its ramp are set here
  Real gravity = 1;        ///< |g|, > 0
  Real ramp = 0.5;         ///< gravity reaches |g| over this time (FlowOptions::body_force_ramp)
  Real t_end = 2;
  Real dt = 0;             ///< > 0: a fixed step; 0: 0.9 of the stability limit
  /// Called after every step; may be empty.
  std::function<void(const FlowSolver&)> on_step;
};

struct HydrostaticRow {
  int nx = 0;
  Index particles = 0, water_particles = 0;
  Real t = 0, dt = 0;
  Index steps = 0;
  /// |p(x_c, 0) - g(t) H| / (g H), p sampled at the bottom's centre (moving least squares over the
  /// walls' and water's pressures), g(t) the gravity in force at the end (a fraction of g while
  /// the ramp lasts).
  Real bottom_pressure = 0, bottom_pressure_error = 0;
  /// max |p - g(t) (H - y)| / (g H) along the vertical centre line, y in [0, H] (41 points).
  Real pressure_profile_error = 0;
  /// max |u| over the water at the end, and its largest value after the ramp, over (g H)^½.
  Real max_speed = 0, max_speed_after_ramp = 0;
  Index surface_particles = 0;
  /// Highest and lowest water particle over the run minus H, in spacings (the surface's stability).
  Real surface_rise = 0, surface_drop = 0;
  Real max_div_u = 0;
  double ppe_iterations_per_step = 0;
  double seconds_setup = 0, seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
  std::vector<Real> line_y, line_p, line_exact;  ///< the centre line's profile
};
/// Runs the tank from rest to t_end. Throws as FlowSolver; ConfigError for bad settings;
/// NumericalError when a particle leaves the tank (the step and the particle named).
HydrostaticRow run_hydrostatic(const HydrostaticRunOptions& options);

}  // namespace vrsph
