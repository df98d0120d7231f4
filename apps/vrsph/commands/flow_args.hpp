// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The `vrsph flow` command's arguments and the helpers its cases share (flow.cpp: the periodic
// vortex, the projection and the cavity; flow_free_surface.cpp: the hydrostatic tank and the
// dam break).
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/flow_study.hpp>
#include <vrsph/io/table.hpp>
#include "../cli_common.hpp"
#include "../vtu_series.hpp"
#include "flow_history.hpp"

namespace vrsph::cli {

struct FlowArgs {
  std::string flow_case = "taylor-green", frame = "eulerian", methods = "vrsph", gradient = "auto", nx = "32,64",
              cloud = "perturbed", scheme = "rk3", viscosity = "explicit", shifting = "none", solver = "auto", vtu_series, kernel = "cubic",
              profile_output, history;
  std::vector<std::string> method_opts;
  int dim = 2, vtu_every = 0, threads = 0;
  int wall_layers = 0;  // 0: the case's own (cavity 1 eulerian / 3 lagrangian, hydrostatic 1, dam break 3)
  double t_end = 0, re = 100, cfl = 0.25, jitter = 0.2, h_factor = 3, hyperviscosity = 0, shift_coefficient = 0, dt = 0,
         steady_tol = 1e-4;
  double support_growth = 0, support_isotropy = 0.3;  // FlowOptions::support_growth, support_isotropy_target
  std::string warm_start = "auto";                     // FlowOptions::warm_start: auto | on | off
  std::optional<double> wall_gap;  // FlowOptions::wall_gap; unset: the case's own (the Lagrangian cavity and the dam break 0.5, else 0)
  // Free-surface cases (flow_free_surface.cpp): |g|, its ramp time, the water's depth and width
  // (a dam break's column: width and height 2 width), the tank's width.
  double gravity = 1, ramp = -1, depth = 0, tank_width = 0;
  double wall_height = 0;  // the hydrostatic tank's walls (TankSpec::wall_height); 0: up to the water's level
  std::string geometry = "martin-moyce";  // the dam break's tank (DamBreakGeometry)
  std::string wall_acceleration = "momentum";  // FlowOptions::wall_acceleration (free-surface cases)
  std::string surface_gradient = "linear";     // FlowOptions::surface_gradient (free-surface cases)
  double surface_film = 0.1;                   // FlowOptions::surface.film_eigenvalue (free-surface cases)
  double shift_limit = 0.25;                   // ShiftingOptions::max_shift (spacings; 0: unbounded)
  bool frame_given = false;     // --frame on the command line (the free-surface cases default to lagrangian)
  bool shifting_given = false;  // --shifting on the command line (the dam break defaults to xu)
  std::uint64_t seed = 1;
  bool allow_unstable = false;
  bool reuse_factorisation = false;  // FlowOptions::reuse_factorisation
  bool reuse_hierarchy = true;       // FlowOptions::reuse_hierarchy
  std::optional<int> pressure_corrections;  // FlowOptions::pressure_corrections; unset: the method's (vrsph 1, else 0)
  OutputOptions out;
};

// The runs of a comparison that blew up (NumericalError: an instability, a failed pressure
// solve, a particle lost; GeometryError raised within a step: particles left without neighbours). A classic scheme that cannot run is a result of the comparison, not a reason to lose
// the others: its row carries the message in `status`, the table is written, and the command
// then fails with the first message (the exit code of a numerical error). Bad input
// (ConfigError, InputError, ...) still stops at once.
struct FailedRuns {
  std::size_t runs = 0;
  std::vector<std::string> messages;
  /// run(); false (and the row `key` + status added to t) when it threw a NumericalError.
  template <class Run>
  bool attempt(Table& t, std::vector<std::pair<std::string, TableCell>> key, Run&& run) {
    ++runs;
    try {
      run();
      return true;
    } catch (const NumericalError& e) {
      record(t, std::move(key), e.what());
      return false;
    } catch (const GeometryError& e) {
      // Particles that lost their neighbours during a step (a Lagrangian run that blew up) end
      // that run, not the comparison; a cloud refused before its first step is bad input.
      if (std::string_view(e.what()).substr(0, 10) != "flow step ") throw;
      record(t, std::move(key), e.what());
      return false;
    }
  }
  void record(Table& t, std::vector<std::pair<std::string, TableCell>> key, const std::string& message) {
    messages.push_back(message);
    key.emplace_back("status", message);
    t.add_row(key);
  }
  void raise_if_any() const {
    if (messages.empty()) return;
    std::string all = messages.front();
    for (std::size_t k = 1; k < messages.size(); ++k) all += "; then: " + messages[k];
    throw NumericalError(detail::concat(messages.size(), " of ", runs, " runs failed (their rows' status says why): ", all));
  }
};

/// The periodic vortex's cloud of one resolution.
FlowCloudSpec cloud_spec(const FlowArgs& a, int nx);
/// The VTU series of the first method's finest run (one series per --vtu-series), else null.
std::unique_ptr<VtuSeries> series_for(const FlowArgs& a, const std::vector<std::string>& methods,
                                      const std::vector<int>& nxs, const std::string& method, int nx);
/// Each particle's support_isotropy at the solver's positions, as a VTU field: where the supports
/// close onto lines or planes.
PointField isotropy_field(const FlowSolver& s);
/// One method's operators, and the flow's options, from the command line.
OperatorsOptions operators_for(const FlowArgs& a, const std::string& method, const std::map<std::string, MethodOptions>& options);
FlowOptions flow_options_for(const FlowArgs& a, const std::string& method, const std::map<std::string, MethodOptions>& options);
/// NaN for every order column of a run that failed (orders skip it).
void skip_orders(std::map<std::string, std::vector<Real>>& errors);
/// Observed orders between consecutive resolutions of one method (the first row has none).
void add_orders(Table& t, std::size_t first, const std::vector<int>& nx, const std::map<std::string, std::vector<Real>>& errors);
/// --case hydrostatic (flow_free_surface.cpp).
void run_hydrostatic_case(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                          const std::map<std::string, MethodOptions>& options);
extern const std::vector<std::string> hydrostatic_columns;
/// --case dam-break (flow_free_surface.cpp).
void run_dam_break_case(const FlowArgs& a, const std::vector<std::string>& methods, const std::vector<int>& nxs,
                        const std::map<std::string, MethodOptions>& options);
extern const std::vector<std::string> dam_break_columns;

}  // namespace vrsph::cli
