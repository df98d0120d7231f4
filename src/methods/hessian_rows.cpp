// SPDX-License-Identifier: BSD-3-Clause
#include "cubic_rows.hpp"
#include <algorithm>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/hessian_rows.hpp>

namespace vrsph {

namespace {

// The targets of every Hessian component among the monomials of degree 1 ... `degree`.
std::vector<cubic_rows::Target> hessian_targets(int dim, int degree) {
  std::vector<cubic_rows::Target> targets;
  for (int k = 0; k < components(OperatorKind::Hessian, dim); ++k) {
    const auto [b, c] = hessian_axes(k, dim);
    std::array<int, 3> alpha{};
    ++alpha[static_cast<std::size_t>(b)];
    ++alpha[static_cast<std::size_t>(c)];
    // ∂_b ∂_c of x^α at the origin, in variables scaled by h: 2 for x_b², 1 for x_b x_c.
    targets.push_back({static_cast<std::size_t>(k), cubic_rows::monomial_index(dim, alpha, degree), b == c ? 2.0 : 1.0, 2});
  }
  return targets;
}

cubic_rows::Outcome fit(const Discretisation& disc, const StencilRequest& req, Stencil& s, int degree, Real max_condition) {
  const auto targets = hessian_targets(disc.cloud.dim, degree);
  if (degree == 2) {
    switch (disc.cloud.dim) {
      case 1: return cubic_rows::correct_rows<2, 1, 2>(disc, req, s, targets, max_condition);
      case 2: return cubic_rows::correct_rows<5, 3, 2>(disc, req, s, targets, max_condition);
      default: return cubic_rows::correct_rows<9, 6, 2>(disc, req, s, targets, max_condition);
    }
  }
  if (degree == 3) {
    switch (disc.cloud.dim) {
      case 1: return cubic_rows::correct_rows<3, 1, 3>(disc, req, s, targets, max_condition);
      case 2: return cubic_rows::correct_rows<9, 3, 3>(disc, req, s, targets, max_condition);
      default: return cubic_rows::correct_rows<19, 6, 3>(disc, req, s, targets, max_condition);
    }
  }
  switch (disc.cloud.dim) {
    case 1: return cubic_rows::correct_rows<4, 1, 4>(disc, req, s, targets, max_condition);
    case 2: return cubic_rows::correct_rows<14, 3, 4>(disc, req, s, targets, max_condition);
    default: return cubic_rows::correct_rows<34, 6, 4>(disc, req, s, targets, max_condition);
  }
}

}  // namespace

Stencil hessian_rows(const Discretisation& disc, const StencilRequest& req, std::string method, int degree,
                     Real max_condition) {
  check<ConfigError>(degree >= 2 && degree <= 4, "hessian rows: the polynomial degree must be 2, 3 or 4, got ", degree);
  const int dim = disc.cloud.dim;
  check<InputError>(disc.neighbours.size() == disc.cloud.size(), "hessian rows: the neighbour list has ",
                    disc.neighbours.size(), " rows for ", disc.cloud.size(), " particles (size mismatch)");
  check<InputError>(req.rows.empty() || static_cast<Index>(req.rows.size()) == disc.cloud.size(), "hessian rows: the row mask has ",
                    req.rows.size(), " entries for ", disc.cloud.size(), " particles (size mismatch)");
  Stencil s = make_stencil_pattern(disc.neighbours, OperatorKind::Hessian, dim, std::move(method));
  cubic_rows::Outcome o = fit(disc, req, s, degree, max_condition);
  // Rows with too few neighbours for the fit, or an ill-conditioned one, take the next lower
  // degree: a box corner without ghosts holds 8 neighbours inside 3 dx (a quartic has 14
  // monomials in 2D, a cubic 9), so its row is exact on quadratics (first order there).
  std::vector<char> retry(static_cast<std::size_t>(disc.cloud.size()), 0);
  for (int lower = degree - 1; !o.kept.empty() && lower >= 2; --lower) {
    std::fill(retry.begin(), retry.end(), 0);
    for (const Index i : o.kept) retry[static_cast<std::size_t>(i)] = 1;
    StencilRequest again = req;
    again.rows = retry;
    o = fit(disc, again, s, lower, max_condition);
  }
  if (!o.kept.empty()) {
    const Index i = o.kept.front();
    const auto dist = disc.neighbours.distances_of(i);
    const Real h = disc.neighbours.radius(i);
    const auto inside = std::count_if(dist.begin(), dist.end(), [h](Real r) { return r < h; });
    const Vec3& x = disc.cloud.positions[static_cast<std::size_t>(i)];
    const auto needed = monomial_exponents(dim, 2).size();
    throw InputError(detail::concat(
        "hessian rows: ", o.kept.size(), " particle(s) cannot have a second-derivative row, the first particle ", i, " (",
        x[0], ", ", x[1], ", ", x[2], "): ", inside, " neighbours inside its support radius ", h,
        static_cast<std::size_t>(inside) < needed
            ? detail::concat(", a row exact on quadratics needs at least ", needed, " (raise h or h_factor)")
            : std::string(", but they do not determine a quadratic (they lie on too few lines or planes)")));
  }
  return s;
}

Stencil build_stencil(const Method& method, const Discretisation& disc, const StencilRequest& req) {
  if (req.kind != OperatorKind::Hessian) return method.build(disc, req);
  return hessian_rows(disc, req, method.info().name);
}

}  // namespace vrsph
