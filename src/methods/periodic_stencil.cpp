// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/neighbours/periodic.hpp>

namespace vrsph {

namespace {
// Row values over the extended cloud: each image takes its original's.
Eigen::MatrixXd expand(const Eigen::MatrixXd& v, const PeriodicImages& im) {
  Eigen::MatrixXd out(im.cloud.size(), v.cols());
  for (Index i = 0; i < im.cloud.size(); ++i) out.row(i) = v.row(im.image_of[static_cast<std::size_t>(i)]);
  return out;
}

// The first N rows, each image column replaced by its original (period > 2 h: no row sees
// one particle twice), sorted by column as a stencil's rows are.
Stencil fold(Stencil s, const PeriodicImages& im) {
  const Index n = im.originals;
  Stencil out;
  out.kind = s.kind;
  out.dim = s.dim;
  out.method = s.method;
  out.values.assign(s.values.size(), {});
  out.row_ptr.assign(static_cast<std::size_t>(n) + 1, 0);
  out.diag.assign(static_cast<std::size_t>(n), 0);
  std::vector<std::pair<Index, Index>> row;  // (original column, entry)
  for (Index i = 0; i < n; ++i) {
    row.clear();
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k)
      row.emplace_back(im.image_of[static_cast<std::size_t>(s.col[static_cast<std::size_t>(k)])], k);
    std::sort(row.begin(), row.end());
    for (const auto& [j, k] : row) {
      const auto sk = static_cast<std::size_t>(k);
      if (j == i) out.diag[static_cast<std::size_t>(i)] = static_cast<Index>(out.col.size());
      out.col.push_back(j);
      for (std::size_t c = 0; c < s.values.size(); ++c) out.values[c].push_back(s.values[c][sk]);
      if (!s.rhs.empty()) out.rhs.push_back(s.rhs[sk]);
    }
    out.row_ptr[static_cast<std::size_t>(i) + 1] = static_cast<Index>(out.col.size());
  }
  const auto first_n = [n](auto& v) {
    if (!v.empty()) v.resize(static_cast<std::size_t>(n));
  };
  out.residual = std::move(s.residual);
  out.local_failure = std::move(s.local_failure);
  out.condition = std::move(s.condition);
  out.xi = std::move(s.xi);
  out.wall_flux = std::move(s.wall_flux);
  out.negative_volumes = std::move(s.negative_volumes);
  first_n(out.residual);
  first_n(out.local_failure);
  first_n(out.condition);
  first_n(out.xi);
  first_n(out.wall_flux);
  first_n(out.negative_volumes);
  return out;
}
}  // namespace

Stencil periodic_stencil(const Method& method, const PointCloud& cloud, const SearchParams& search, KernelType kernel,
                         Real spacing, const StencilRequest& request) {
  check<InputError>(cloud.domain.any_periodic(), "periodic_stencil: the cloud's box has no periodic axis");
  const Index n = cloud.size();
  const Real h = search.radii.empty() ? search.radius : *std::max_element(search.radii.begin(), search.radii.end());
  check_periodic_cloud(cloud, h);
  const int reach = std::max(method.reach(), request.coefficient_gradient == nullptr &&
                                                     method.needs_coefficient_gradient(request.use)
                                                 ? method.estimated_gradient_reach()
                                                 : 0);
  const PeriodicImages im = periodic_images(cloud, reach * h * 1.05);
  SearchParams sp = search;
  sp.wrap_periodic = false;
  sp.min_neighbours = 0;  // an image's row may be cut; the originals' rows are checked below
  if (!search.radii.empty()) {
    sp.radii.resize(static_cast<std::size_t>(im.cloud.size()));
    for (std::size_t k = 0; k < sp.radii.size(); ++k) sp.radii[k] = search.radii[static_cast<std::size_t>(im.image_of[k])];
  }
  const NeighbourList nl = find_neighbours(im.cloud, sp);
  for (Index i = 0; i < n; ++i)
    check<GeometryError>(nl.count(i) >= search.min_neighbours || cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost,
                         "particle ", i, " has ", nl.count(i), " neighbours (need at least ", search.min_neighbours,
                         "); increase the smoothing radius");
  std::vector<char> rows(static_cast<std::size_t>(im.cloud.size()), 0);
  for (Index i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = request.rows.empty() || request.rows[static_cast<std::size_t>(i)];
  StencilRequest req = request;
  req.rows = rows;
  Field a;
  Eigen::MatrixXd grad_a, mobility;
  if (request.coefficient) {
    a = expand(*request.coefficient, im);
    req.coefficient = &a;
  }
  if (request.coefficient_gradient) {
    grad_a = expand(*request.coefficient_gradient, im);
    req.coefficient_gradient = &grad_a;
  }
  if (request.mobility) {
    mobility = expand(*request.mobility, im);
    req.mobility = &mobility;
  }
  const Discretisation disc{im.cloud, nl, kernel, spacing, n, length_scale(cloud)};
  return fold(method.build(disc, req), im);
}

}  // namespace vrsph
