// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include "geometry_args.hpp"

namespace vrsph::cli {

GeometryCloud make_geometry_cloud(const GeometryRequest& r) {
  check<ConfigError>(r.fill == "uniform" || r.fill == "perturbed" || r.fill == "blue-noise",
                     "the fill of a geometry must be uniform, perturbed or blue-noise, got '", r.fill, "'");
  check<ConfigError>(r.fill == "perturbed" || !r.delta, "--delta applies to the perturbed lattice, not to ", r.fill);
  check<ConfigError>(r.neumann_where.empty() || r.dirichlet_where.empty(), "give the Neumann or the Dirichlet part of "
                     "the boundary by expression, not both (the other boundary particles get the other kind)");
  GeometryFill fill;
  fill.spacing = r.spacing;
  fill.delta = r.fill == "perturbed" ? r.delta.value_or(0.3) : 0;
  fill.seed = r.seed;
  fill.pattern = r.fill == "blue-noise" ? FillPattern::BlueNoise : FillPattern::Lattice;
  fill.part = r.part;
  fill.parts = r.parts;
  GeometryCloud g = fill_geometry(r.path, fill);
  if (!r.neumann_where.empty() || !r.dirichlet_where.empty()) {
    const bool by_neumann = !r.neumann_where.empty();
    const Expression select(by_neumann ? r.neumann_where : r.dirichlet_where);
    const std::string& option = by_neumann ? r.neumann_option : r.dirichlet_option;
    tag_boundary(g.cloud, [&](const Vec3& x) {
      const Real v = select(x);
      // NaN != 0 would tag the particle silently: a condition must be a number everywhere.
      check<InputError>(std::isfinite(v), option, " '", printable(select.text(), 200), "' is not finite (", v,
                        ") at (", x[0], ", ", x[1], ", ", x[2], ")");
      return (v != 0) == by_neumann;
    });
  }
  return g;
}

}  // namespace vrsph::cli
