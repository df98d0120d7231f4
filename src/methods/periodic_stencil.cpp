// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <cstdint>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/hessian_rows.hpp>
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

// The two shifts added (codes per axis in {-1, 0, 1}); no code when a sum leaves that range.
int combined_shift(std::uint8_t a, std::uint8_t b) {
  std::array<int, 3> s{};
  for (int k = 0; k < 3; ++k) {
    s[static_cast<std::size_t>(k)] = axis_shift(a, k) + axis_shift(b, k);
    if (s[static_cast<std::size_t>(k)] < -1 || s[static_cast<std::size_t>(k)] > 1) return -1;
  }
  return shift_code(s[0], s[1], s[2]);
}

// The images' neighbour list from the originals' minimum-image list: an image's row is its
// original's moved by the image's shift, keeping the entries whose image exists.
NeighbourList list_of_images(const PeriodicImages& im, const NeighbourList& nl) {
  std::vector<std::vector<std::pair<std::uint8_t, Index>>> images_of(static_cast<std::size_t>(im.originals));
  for (Index p = 0; p < im.cloud.size(); ++p)
    images_of[static_cast<std::size_t>(im.image_of[static_cast<std::size_t>(p)])].emplace_back(im.shift[static_cast<std::size_t>(p)], p);
  const auto find = [&](Index j, int code) -> Index {
    for (const auto& [c, p] : images_of[static_cast<std::size_t>(j)])
      if (c == code) return p;
    return -1;
  };
  NeighbourList out;
  const Index m = im.cloud.size();
  out.offsets.assign(static_cast<std::size_t>(m) + 1, 0);
  out.radii.resize(static_cast<std::size_t>(m));
  std::vector<std::pair<Index, Real>> row;
  std::vector<Index> indices;
  std::vector<Real> distances;
  for (Index p = 0; p < m; ++p) {
    const auto sp = static_cast<std::size_t>(p);
    const Index o = im.image_of[sp];
    out.radii[sp] = nl.radius(o);
    row.clear();
    for (Index k = nl.offsets[static_cast<std::size_t>(o)]; k < nl.offsets[static_cast<std::size_t>(o) + 1]; ++k) {
      const auto sk = static_cast<std::size_t>(k);
      const int code = combined_shift(im.shift[sp], nl.shifts[sk]);
      const Index q = code < 0 ? -1 : find(nl.indices[sk], code);
      if (q >= 0) row.emplace_back(q, nl.distances.empty() ? (im.cloud.positions[static_cast<std::size_t>(q)] - im.cloud.positions[sp]).norm() : nl.distances[sk]);
    }
    std::sort(row.begin(), row.end());
    for (const auto& [q, r] : row) {
      indices.push_back(q);
      distances.push_back(r);
    }
    out.offsets[sp + 1] = static_cast<Index>(indices.size());
  }
  out.indices.assign(indices.begin(), indices.end());
  out.distances.assign(distances.begin(), distances.end());
  return out;
}

// The rows over the images (every method unchanged), folded onto the originals.
Stencil build_on_images(const Method& method, const PointCloud& cloud, const PeriodicImages& im, const NeighbourList& nl,
                        KernelType kernel, Real spacing, const StencilRequest& request) {
  const Index n = cloud.size();
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
  return fold(build_stencil(method, disc, req), im);
}

// The images within the rows' reach of a periodic face.
PeriodicImages images_for(const Method& method, const PointCloud& cloud, Real h, const StencilRequest& request) {
  check<InputError>(cloud.domain.any_periodic(), "periodic_stencil: the cloud's box has no periodic axis");
  check_periodic_cloud(cloud, h);
  const Real reach = rows_reach(method, request.use, request.coefficient_gradient != nullptr);
  return periodic_images(cloud, reach * h * 1.05);
}
}  // namespace

Stencil periodic_stencil(const Method& method, const PointCloud& cloud, const SearchParams& search, KernelType kernel,
                         Real spacing, const StencilRequest& request) {
  const Real h = search.radii.empty() ? search.radius : *std::max_element(search.radii.begin(), search.radii.end());
  const PeriodicImages im = images_for(method, cloud, h, request);
  return build_on_images(method, cloud, im, im.search(search), kernel, spacing, request);
}

Stencil periodic_stencil(const Method& method, const PointCloud& cloud, const NeighbourList& neighbours,
                         KernelType kernel, Real spacing, const StencilRequest& request) {
  check<InputError>(neighbours.size() == cloud.size() && neighbours.radii.size() == static_cast<std::size_t>(cloud.size()),
                    "periodic_stencil: a neighbour list of ", neighbours.size(), " rows for ", cloud.size(), " particles");
  check<InputError>(neighbours.shifts.size() == static_cast<std::size_t>(neighbours.total()),
                    "periodic_stencil: the neighbour list has no periodic shift codes (make it with find_neighbours or "
                    "neighbour_list_from on the periodic cloud)");
  const PeriodicImages im =
      images_for(method, cloud, *std::max_element(neighbours.radii.begin(), neighbours.radii.end()), request);
  return build_on_images(method, cloud, im, list_of_images(im, neighbours), kernel, spacing, request);
}

}  // namespace vrsph
