// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Geometries in the CLI: `vrsph cloud --geometry` and `vrsph solve|study --geometry` fill a
// polygon or closed surface the same way, with boundary tags from expressions.
#include <cstdint>
#include <optional>
#include <string>
#include <vrsph/cloud/geometry.hpp>

namespace vrsph::cli {

struct GeometryRequest {
  std::string path;
  double spacing = 0;
  std::string fill = "uniform";         ///< uniform | perturbed | blue-noise
  std::optional<double> delta;          ///< perturbed: amplitude in spacings (default 0.3)
  std::uint64_t seed = 1;
  std::string neumann_where, dirichlet_where;  ///< expressions; at most one of them
  /// The options they came from, for messages (`vrsph cloud` calls them --neumann/--dirichlet).
  std::string neumann_option = "--neumann-where", dirichlet_option = "--dirichlet-where";
  int part = 0, parts = 1;                      ///< lattice fills: this part only (GeometryFill)
};

/// Checks the request (fill name, delta only with perturbed, not both expressions), fills the
/// geometry and tags its boundary: Neumann where neumann_where is non-zero, or everywhere
/// dirichlet_where is zero; all Dirichlet without either.
GeometryCloud make_geometry_cloud(const GeometryRequest& request);

}  // namespace vrsph::cli
