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
#include <limits>
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
/// Martin & Moyce's residual column height for n² = 2 (their Table 6, the tabulated (τ, H) with
/// τ = t (g/a)^½ and H = η / (n² a)), in this tank's units (a = L): z_over_l holds η/L = 2H at
/// T = t (2g/L)^½ = √2 τ.
const SurgeCurve& martin_moyce_height_reference();

/// The tank of the run:
///  - MartinMoyce: a column L wide and 2L high in a tank 4L wide (walls 3L high); T = t (2g/L)^½,
///    fronts against Martin & Moyce and Koshizuka & Oka (above);
///  - Buchner: a column 2H wide and H high in a tank 5.366 H wide (walls 6H high), the MARIN
///    experiment of Buchner (PhD thesis, TU Delft, 2002) used by Marrone et al. (Comput. Methods
///    Appl. Mech. Engrg. 200 (2011) 1526) and Adami, Hu & Adams (2012); T = t (g/H)^½, and the
///    pressure p/(ρgH) on the far wall at probe P1, 0.2667 H above the floor, against Buchner's
///    record (probe_reference).
enum class DamBreakGeometry { MartinMoyce, Buchner };
/// "martin-moyce" | "buchner"; ConfigError otherwise.
DamBreakGeometry parse_dam_break_geometry(const std::string& name);
std::string to_string(DamBreakGeometry g);
/// Buchner's (2002) pressure at P1, p/(ρgH) against T = t (g/H)^½, read off the thesis' figure
/// (the digitisation TrixiParticles.jl's validation publishes); z_over_l holds the pressure.
const SurgeCurve& buchner_probe_reference();
/// The probe's height above the floor in H (Buchner's P1: 160 mm of a 600 mm column).
constexpr Real buchner_probe_height = 160.0 / 600.0;

struct DamBreakRunOptions {
  DamBreakGeometry geometry = DamBreakGeometry::MartinMoyce;
  int nx = 20;             ///< intervals across the column (dx = L / nx); Buchner: across its height H
  Real jitter = 0;         ///< the water's particles perturbed by U(-jitter dx, jitter dx)
  std::uint64_t seed = 1;
  int wall_layers = 3;     ///< layers of wall particles
  FlowOptions flow;        ///< frame must be Lagrangian; free_surface and body_force are set here
  Real t_star_end = 3;     ///< stop at T (the run goes on after the front reaches the far wall)
  Real cfl = 0.25;         ///< dt <= cfl dx / max |u| (and the stability limit)
  Real sample = 0.1;       ///< a row every this much T
  /// FlowOptions::wall_gap unless `flow` sets one (< 0: none). The water's impact on the far
  /// wall pressed its first layer through the wall without it (docs/free_surface.md).
  Real wall_gap = 0.5;
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
  /// Martin & Moyce's column height η/L at t_star (NaN outside their table, and in Buchner's tank).
  Real experiment_height = std::numeric_limits<Real>::quiet_NaN();
  Real max_speed = 0;              ///< over the water, / (g L)^½
  Index surface_particles = 0;
  Real min_spacing = 0;
  /// Buchner: p/(ρgH) at probe P1 (the kernel-weighted mean of the water's pressure within the
  /// support of the point on the far wall's face; 0 when no water is there) and Buchner's
  /// record at t_star (NaN beyond it); NaN in the other geometry.
  Real probe_pressure = std::numeric_limits<Real>::quiet_NaN();
  Real probe_reference = std::numeric_limits<Real>::quiet_NaN();
};

struct DamBreakRun {
  int nx = 0;
  Index particles = 0, water_particles = 0;
  Index steps = 0;
  Real t_star = 0;                 ///< reached
  bool reached_far_wall = false;
  Real far_wall_t_star = 0;        ///< T at which the front reached the far wall (when it did)
  /// Why the run stopped early (a particle lost through a wall, one left without neighbours):
  /// the error's message naming the step and the particle; empty when it ran to its end. The
  /// samples before it are kept.
  std::string stopped;
  std::vector<DamBreakSample> samples;
  /// Largest front deviation outside the experiments' spread while z/L <= 3.5, / L (Martin–Moyce).
  Real max_outside_experiments = 0;
  /// Largest |column height - Martin & Moyce's| / L over the samples inside their table taken
  /// before the front reached the far wall (their plane had none: the wave reflected there
  /// comes back to the column later); NaN when there was none, and in Buchner's tank.
  Real max_height_deviation = std::numeric_limits<Real>::quiet_NaN();
  /// Buchner: the probe's first peak (largest p/(ρgH) for T <= 3.5) and when, the mean over
  /// 3 <= T <= 5 (the plateau before the wave falls back), and Buchner's (0.687 at T = 2.77,
  /// mean 0.55); NaN when the run did not reach those times or in the other geometry.
  Real probe_peak = std::numeric_limits<Real>::quiet_NaN(), probe_peak_t_star = std::numeric_limits<Real>::quiet_NaN();
  Real probe_plateau = std::numeric_limits<Real>::quiet_NaN();
  Real reference_peak = std::numeric_limits<Real>::quiet_NaN(), reference_peak_t_star = std::numeric_limits<Real>::quiet_NaN();
  Real reference_plateau = std::numeric_limits<Real>::quiet_NaN();
  double ppe_iterations_per_step = 0;
  double seconds_setup = 0, seconds_per_step = 0, seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;
  double seconds_viscous = 0;  ///< per step: the implicit viscous set-ups and solves
};
/// Runs the dam break. ConfigError for bad settings (an Eulerian frame); a step that fails
/// (NumericalError, or GeometryError within a step) ends the run with `stopped` set.
DamBreakRun run_dam_break(const DamBreakRunOptions& options);

}  // namespace vrsph
