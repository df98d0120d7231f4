// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>
#include "../neighbours/nearest_particles.hpp"

namespace vrsph {

namespace {
// The candidate farthest from its nearest particle.
CoveringRadius farthest_candidate(const PointCloud& cloud, const std::vector<Vec3>& cand) {
  std::vector<Real> dist;
  std::vector<Index> idx;
  detail::nearest_particles(cloud, cand, dist, idx);
  CoveringRadius out;
  out.candidates = static_cast<Index>(cand.size());
  for (std::size_t k = 0; k < cand.size(); ++k)
    if (dist[k] > out.radius) {
      out.radius = dist[k];
      out.point = cand[k];
      out.nearest = idx[k];
    }
  return out;
}
}  // namespace

namespace {
// Every candidate of a box or ball domain (see the header), inside the closed domain.
std::vector<Vec3> box_or_ball_candidates(const PointCloud& cloud, Real spacing) {
  const Domain& dom = cloud.domain;
  std::vector<Vec3> cand;
  if (cloud.dim == 1) {
    std::vector<Real> x;
    for (const auto& p : cloud.positions) x.push_back(p[0]);
    std::sort(x.begin(), x.end());
    for (std::size_t k = 0; k + 1 < x.size(); ++k) cand.emplace_back(0.5 * (x[k] + x[k + 1]), 0, 0);
  } else if (cloud.size() > cloud.dim) {
    cand = detail::covering_candidates(cloud);
  }
  // Domain corners / extreme points, and on a sphere the point farthest from each particle.
  if (dom.shape == Domain::Shape::Box) {
    for (int mask = 0; mask < (1 << cloud.dim); ++mask) {
      Vec3 c = Vec3::Zero();
      for (int k = 0; k < cloud.dim; ++k) c[k] = (mask >> k) & 1 ? dom.hi[k] : dom.lo[k];
      cand.push_back(c);
    }
  } else {
    for (const auto& p : cloud.positions) {
      const Vec3 r = p - dom.centre;
      if (r.norm() > 1e-300) cand.push_back(dom.centre - dom.radius * r.normalized());
    }
    if (cloud.dim == 1) {
      cand.emplace_back(dom.centre[0] - dom.radius, 0, 0);
      cand.emplace_back(dom.centre[0] + dom.radius, 0, 0);
    }
  }
  // Keep candidates in the closed domain (clipped to it against round-off).
  const Real tol = 1e-12 * std::max<Real>(1, spacing);
  std::vector<Vec3> inside;
  inside.reserve(cand.size());
  for (auto x : cand) {
    for (int k = cloud.dim; k < 3; ++k) x[k] = 0;
    if (!x.allFinite() || dom.signed_distance(x) < -tol) continue;
    inside.push_back(x);
  }
  return inside;
}

void check_box_or_ball(const PointCloud& cloud) {
  check<InputError>(cloud.domain.shape == Domain::Shape::Box || cloud.domain.shape == Domain::Shape::Ball,
                    "the covering radius needs a box or ball domain (the cloud has none)");
}
}  // namespace

namespace {
// A box periodic along some axes: the largest empty ball of the periodic point set, from the
// cloud extended by its images within w of the periodic faces, the originals owned
// (covering_radius_of_owned, exact once r_N <= w / 2; w doubles from 3 spacings until it is).
CoveringRadius periodic_covering_radius(const PointCloud& cloud) {
  const Domain& dom = cloud.domain;
  check_periodic_cloud(cloud, 0);  // every particle inside the box along the periodic axes
  const Real min_period = dom.shortest_period();
  const Real spacing = estimate_spacing(cloud), cap = (1 - 1e-9) * min_period;
  for (Real width = std::min(3 * spacing, cap);; width = std::min(2 * width, cap)) {
    const PeriodicImages images = periodic_images(cloud, width);
    std::vector<char> owned(static_cast<std::size_t>(images.cloud.size()), 0);
    std::fill(owned.begin(), owned.begin() + cloud.size(), 1);
    CoveringRadius r = covering_radius_of_owned(images.cloud, owned, spacing);
    if (r.radius <= 0.5 * width) {
      r.nearest = images.image_of[static_cast<std::size_t>(r.nearest)];
      r.point = dom.wrap(r.point);
      return r;
    }
    check<ConfigError>(width < cap, "the covering radius of this periodic cloud (", r.radius,
                       ") reaches half the period ", min_period, ": too few particles across the box");
  }
}
}  // namespace

CoveringRadius covering_radius(const PointCloud& cloud) {
  validate(cloud);
  check_box_or_ball(cloud);
  check<InputError>(cloud.size() > cloud.dim, "the covering radius needs more than ", cloud.dim, " particles");
  if (cloud.domain.any_periodic()) return periodic_covering_radius(cloud);
  return farthest_candidate(cloud, box_or_ball_candidates(cloud, estimate_spacing(cloud)));
}

CoveringRadius covering_radius_of_owned(const PointCloud& local, std::span<const char> owned, Real spacing) {
  validate(local);
  check_box_or_ball(local);
  check<InputError>(static_cast<Index>(owned.size()) == local.size(), "covering_radius_of_owned: ", owned.size(),
                    " owner flags for ", local.size(), " particles");
  CoveringRadius out;
  PointCloud mine;
  mine.dim = local.dim;
  for (Index i = 0; i < local.size(); ++i)
    if (owned[static_cast<std::size_t>(i)]) mine.positions.push_back(local.positions[static_cast<std::size_t>(i)]);
  if (mine.positions.empty()) return out;
  mine.tags.assign(mine.positions.size(), Tag::Interior);
  const std::vector<Vec3> cand = box_or_ball_candidates(local, spacing);
  std::vector<Real> dist, dist_mine;
  std::vector<Index> idx, idx_mine;
  detail::nearest_particles(local, cand, dist, idx);
  detail::nearest_particles(mine, cand, dist_mine, idx_mine);
  out.candidates = static_cast<Index>(cand.size());
  for (std::size_t k = 0; k < cand.size(); ++k) {
    // A candidate whose nearest particle is (also) an owned one: on a lattice the Voronoi
    // vertices are equidistant from particles of several ranks, and each counts it.
    if (dist_mine[k] > dist[k] * (1 + 1e-12) + 1e-300 || !(dist[k] > out.radius)) continue;
    out.radius = dist[k];
    out.point = cand[k];
    out.nearest = idx[k];
  }
  return out;
}

CoveringRadius covering_radius(const PointCloud& cloud, const std::function<bool(const Vec3&)>& inside,
                               const std::vector<Vec3>& boundary_sample, Real boundary_step) {
  validate(cloud);
  check<InputError>(cloud.dim == 2 || cloud.dim == 3, "the covering radius of a general domain needs a 2D or 3D cloud");
  check<InputError>(cloud.size() > cloud.dim, "the covering radius needs more than ", cloud.dim, " particles");
  check<ConfigError>(std::isfinite(boundary_step) && boundary_step >= 0, "the boundary sampling step must be finite and "
                     ">= 0, got ", boundary_step);
  // Voronoi vertices only: a box or ball domain's boundary hits are not this domain's.
  std::optional<PointCloud> unbounded;
  if (cloud.domain.shape != Domain::Shape::None) {
    unbounded = cloud;
    unbounded->domain = Domain{};
  }
  std::vector<Vec3> cand;
  for (const Vec3& x : detail::covering_candidates(unbounded ? *unbounded : cloud))
    if (x.allFinite() && inside(x)) cand.push_back(x);
  cand.insert(cand.end(), boundary_sample.begin(), boundary_sample.end());
  CoveringRadius out = farthest_candidate(cloud, cand);
  out.uncertainty = boundary_step;
  return out;
}

}  // namespace vrsph
