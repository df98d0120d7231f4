// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The dam break (docs/free_surface.md): a water column of width L and height 2L released at
// rest in a tank 4L wide, its surge front z along the floor against T = t (2g/L)^½, beside the
// experiments of Martin & Moyce (Phil. Trans. R. Soc. A 244 (1952) 312–324, Fig. 3, n² = 2,
// a = 1.125 in and 2.25 in) and the MPS result of Koshizuka & Oka (Nucl. Sci. Eng. 123 (1996)
// 421–434). The tabulated points are read off the papers' figures (the digitisation PySPH's
// examples publish); Lagrangian frame, free surface, walls of several layers.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>
#include <vrsph/flow/flow_solver.hpp>

namespace vrsph {

/// One published curve: front position z/L at times T = t (2g/L)^½.
struct SurgeCurve {
  std::string name;
  std::vector<Real> t_star, z_over_l;
  /// Linear interpolation; NaN outside the curve's range.
  Real at(Real t) const;
};
/// Martin & Moyce a = 1.125 in, a = 2.25 in, and Koshizuka & Oka's MPS.
const std::vector<SurgeCurve>& dam_break_references();

struct DamBreakRunOptions {
  int nx = 20;             ///< intervals across the column (dx = L / nx)
  Real jitter = 0;         ///< the water's particles perturbed by U(-jitter dx, jitter dx)
  std::uint64_t seed = 1;
  int wall_layers = 3;     ///< layers of wall particles
  FlowOptions flow;        ///< frame must be Lagrangian; free_surface and body_force are set here
  Real t_star_end = 3;     ///< stop at T = t (2g/L)^½ (or when the front reaches the far wall)
  Real cfl = 0.25;         ///< dt <= cfl dx / max |u| (and the stability limit)
  Real sample = 0.1;       ///< a row every this much T
  /// Called after every step; may be empty.
  std::function<void(const FlowSolver&)> on_step;
};

struct DamBreakSample {
  Real t_star = 0;
  Real front_z_over_l = 0;         ///< the water's farthest particle along the floor, / L
  Real column_height_over_l = 0;   ///< the water's highest particle at the left wall (x < 2 dx), / L
  /// The experiments' spread at t_star (NaN beyond their range) and how far the front lies
  /// outside it (0 inside).
  Real experiment_low = 0, experiment_high = 0, outside_experiments = 0;
  Real mps = 0;                    ///< Koshizuka & Oka at t_star (NaN beyond its range)
  Real max_speed = 0;              ///< over the water, / (g L)^½
  Index surface_particles = 0;
  Real min_spacing = 0;
};

struct DamBreakRun {
  int nx = 0;
  Index particles = 0, water_particles = 0;
  Index steps = 0;
  Real t_star = 0;                 ///< reached
  bool reached_far_wall = false;
  /// Why the run stopped early (a particle lost through a wall, one left without neighbours):
  /// the error's message naming the step and the particle; empty when it ran to its end. The
  /// samples before it are kept.
  std::string stopped;
  std::vector<DamBreakSample> samples;
  /// Largest front deviation outside the experiments' spread while z/L <= 3.5, / L.
  Real max_outside_experiments = 0;
  double ppe_iterations_per_step = 0;
  double seconds_setup = 0, seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
};
/// Runs the dam break. ConfigError for bad settings (an Eulerian frame); a step that fails
/// (NumericalError, or GeometryError within a step) ends the run with `stopped` set.
DamBreakRun run_dam_break(const DamBreakRunOptions& options);

}  // namespace vrsph
