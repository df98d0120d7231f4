// SPDX-License-Identifier: BSD-3-Clause
// Periodic images and the minimum-image neighbour search (periodic.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>
#include "two_pass.hpp"

namespace vrsph {

Vec3 periodic_shift(const Domain& domain, std::uint8_t code) {
  Vec3 s = Vec3::Zero();
  for (int k = 0; k < std::min(domain.dim, 3); ++k) s[k] = static_cast<Real>(axis_shift(code, k)) * domain.period(k);
  return s;
}

void check_periodic_cloud(const PointCloud& cloud, Real radius) {
  const Domain& d = cloud.domain;
  for (int k = 0; k < cloud.dim; ++k) {
    if (!d.periodic[static_cast<std::size_t>(k)]) continue;
    check<InputError>(d.period(k) > 2 * radius, "periodic axis ", "xyz"[k], ": the period ", d.period(k),
                      " must be larger than twice the support radius ", radius,
                      " (else a particle meets two images of one neighbour); use a smaller h or a longer box");
    for (Index i = 0; i < cloud.size(); ++i) {
      const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
      check<InputError>(x[k] >= d.lo[k] && x[k] < d.hi[k], "particle ", i, " at (", x[0], ", ", x[1], ", ", x[2],
                        ") lies outside the periodic box [", d.lo[k], ", ", d.hi[k], ") along ", "xyz"[k],
                        ": wrap the positions into the box (Domain::wrap; in Python Operators.wrap)");
    }
  }
}

std::vector<Real> minimum_image_kth_neighbour_distance(const PointCloud& cloud, int k) {
  std::vector<Real> plain = kth_neighbour_distance(cloud, k);
  if (!cloud.domain.any_periodic()) return plain;
  // A plain distance bounds the minimum-image one from above (its candidates are a subset), so
  // the images within the largest plain distance of a face hold every nearer neighbour.
  const Real width = *std::max_element(plain.begin(), plain.end());
  for (int a = 0; a < cloud.dim; ++a)
    check<ConfigError>(!cloud.domain.periodic[static_cast<std::size_t>(a)] || 2 * width < cloud.domain.period(a),
                       "the distance to the ", k, "-th neighbour (up to ", width, ") reaches half the period ",
                       cloud.domain.period(a), " along ", "xyz"[a],
                       ": too few particles across the periodic box for knn radii (use a smaller k or more particles)");
  const PeriodicImages images = periodic_images(cloud, width);
  std::vector<Real> d = kth_neighbour_distance(images.cloud, k);
  d.resize(static_cast<std::size_t>(cloud.size()));  // the originals come first
  return d;
}

PeriodicImages periodic_images(const PointCloud& cloud, Real width) {
  const Domain& d = cloud.domain;
  check_image_width(d, cloud.dim, width, "rows read particles up to");
  PeriodicImages out;
  out.cloud = cloud;
  out.originals = cloud.size();
  out.image_of.resize(static_cast<std::size_t>(cloud.size()));
  std::iota(out.image_of.begin(), out.image_of.end(), 0);
  out.shift.assign(static_cast<std::size_t>(cloud.size()), no_shift);
  const bool normals = cloud.has_normals();
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = cloud.positions[si];
    for (const std::uint8_t code : image_codes(d, cloud.dim, x, width)) {
      if (code == no_shift) continue;
      out.cloud.positions.push_back(x + periodic_shift(d, code));
      out.cloud.tags.push_back(cloud.tags[si]);
      if (normals) out.cloud.normals.push_back(cloud.normals[si]);
      out.image_of.push_back(i);
      out.shift.push_back(code);
    }
  }
  return out;
}

std::vector<std::uint8_t> image_codes(const Domain& d, int dim, const Vec3& x, Real width) {
  // Per axis: the shifts that bring an image within `width` of the box (0 always).
  std::array<std::array<int, 3>, 3> options{};
  std::array<std::size_t, 3> count{1, 1, 1};
  for (int k = 0; k < std::min(dim, 3); ++k) {
    const auto sk = static_cast<std::size_t>(k);
    if (!d.periodic[sk]) continue;
    if (x[k] - d.lo[k] < width) options[sk][count[sk]++] = 1;
    if (d.hi[k] - x[k] <= width) options[sk][count[sk]++] = -1;
  }
  std::vector<std::uint8_t> codes;
  for (std::size_t a = 0; a < count[0]; ++a)
    for (std::size_t b = 0; b < count[1]; ++b)
      for (std::size_t c = 0; c < count[2]; ++c)
        codes.push_back(shift_code(options[0][a], options[1][b], options[2][c]));
  return codes;
}

void check_image_width(const Domain& d, int dim, Real width, const char* what) {
  for (int k = 0; k < std::min(dim, 3); ++k)
    check<ConfigError>(!d.periodic[static_cast<std::size_t>(k)] || width < d.period(k), "periodic axis ", "xyz"[k],
                       ": ", what, " ", width, " away, beyond one period ", d.period(k),
                       "; use a smaller h or a longer box");
}

Eigen::MatrixXd PeriodicImages::expand(const Eigen::MatrixXd& values) const {
  Eigen::MatrixXd out(cloud.size(), values.cols());
  for (Index i = 0; i < cloud.size(); ++i) out.row(i) = values.row(image_of[static_cast<std::size_t>(i)]);
  return out;
}

Field PeriodicImages::expand(const Field& values) const {
  Field out(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) out[i] = values[image_of[static_cast<std::size_t>(i)]];
  return out;
}

NeighbourList PeriodicImages::search(const SearchParams& search) const {
  SearchParams sp = search;
  sp.wrap_periodic = false;  // the images are here
  sp.min_neighbours = 0;     // checked below, on the originals' rows only
  if (!search.radii.empty()) {
    sp.radii.resize(static_cast<std::size_t>(cloud.size()));
    for (std::size_t k = 0; k < sp.radii.size(); ++k) sp.radii[k] = search.radii[static_cast<std::size_t>(image_of[k])];
  }
  NeighbourList nl = find_neighbours(cloud, sp);
  std::vector<char> originals_only(static_cast<std::size_t>(cloud.size()), 0);
  std::fill(originals_only.begin(), originals_only.begin() + originals, 1);
  detail::check_min_neighbours(cloud, nl, nl.radii, search.min_neighbours, search.include_self, originals_only);
  return nl;
}

namespace detail {
// Minimum-image search: the plain search over the cloud and its images within the largest
// radius; each original's row then names the originals, with the shift of the image seen.
NeighbourList periodic_search(const PointCloud& cloud, const SearchParams& params, NeighbourList out) {
  const std::vector<Real> radii = resolve_radii(cloud, params);
  const Real width = *std::max_element(radii.begin(), radii.end());
  check_periodic_cloud(cloud, width);
  const PeriodicImages im = periodic_images(cloud, width);
  SearchParams sp = params;
  sp.radii = radii;
  const NeighbourList ext = im.search(sp);
  const Index n = cloud.size();
  out.offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Index i = 0; i < n; ++i) out.offsets[static_cast<std::size_t>(i) + 1] = out.offsets[static_cast<std::size_t>(i)] + ext.count(i);
  const auto total = static_cast<std::size_t>(out.offsets.back());
  resize_for_overwrite(out.indices, total);
  if (!ext.distances.empty())
    resize_for_overwrite(out.distances, total);
  else
    out.distances.clear();
  out.shifts.resize(total);
  out.radii.assign(radii.begin(), radii.end());
  // Rows in parallel (each writes its own slots): a moving periodic cloud runs this at every
  // Verlet search.
#pragma omp parallel
  {
    std::vector<std::pair<Index, std::size_t>> row;
#pragma omp for schedule(dynamic, 256)
    for (Index i = 0; i < n; ++i) {
      const auto b = static_cast<std::size_t>(ext.offsets[static_cast<std::size_t>(i)]);
      const auto nbr = ext.of(i);
      row.clear();
      for (std::size_t k = 0; k < nbr.size(); ++k) row.emplace_back(im.image_of[static_cast<std::size_t>(nbr[k])], b + k);
      std::sort(row.begin(), row.end());  // by the original's index, as a plain search lists them
      auto at = static_cast<std::size_t>(out.offsets[static_cast<std::size_t>(i)]);
      for (const auto& [j, e] : row) {
        out.indices[at] = j;
        if (!ext.distances.empty()) out.distances[at] = ext.distances[e];
        out.shifts[at] = im.shift[static_cast<std::size_t>(ext.indices[e])];
        ++at;
      }
    }
  }
  return out;
}
}  // namespace detail

}  // namespace vrsph
