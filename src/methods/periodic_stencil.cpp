// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/neighbours/periodic.hpp>

namespace vrsph {

namespace {
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
  const int reach = rows_reach(method, request.use, request.coefficient_gradient != nullptr);
  const PeriodicImages im = periodic_images(cloud, reach * h * 1.05);
  const NeighbourList nl = im.search(search);
  std::vector<char> rows(static_cast<std::size_t>(im.cloud.size()), 0);
  for (Index i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = request.rows.empty() || request.rows[static_cast<std::size_t>(i)];
  StencilRequest req = request;
  req.rows = rows;
  Field a;
  Eigen::MatrixXd grad_a, mobility;
  if (request.coefficient) {
    a = im.expand(*request.coefficient);
    req.coefficient = &a;
  }
  if (request.coefficient_gradient) {
    grad_a = im.expand(*request.coefficient_gradient);
    req.coefficient_gradient = &grad_a;
  }
  if (request.mobility) {
    mobility = im.expand(*request.mobility);
    req.mobility = &mobility;
  }
  const Discretisation disc{im.cloud, nl, kernel, spacing, n, length_scale(cloud)};
  return fold(method.build(disc, req), im);
}

}  // namespace vrsph
