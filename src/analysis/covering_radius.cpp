#include <algorithm>
#include <cmath>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

namespace detail {
// Nearest particle of each query point (k-d tree); defined in neighbours/kd_tree.cpp.
void nearest_particles(const PointCloud& cloud, const std::vector<Vec3>& queries, std::vector<Real>& dist,
                       std::vector<Index>& index);
}  // namespace detail

CoveringRadius covering_radius(const PointCloud& cloud) {
  validate(cloud);
  const Domain& dom = cloud.domain;
  check<InputError>(dom.shape == Domain::Shape::Box || dom.shape == Domain::Shape::Ball,
                    "the covering radius needs a box or ball domain (the cloud has none)");
  check<InputError>(cloud.size() > cloud.dim, "the covering radius needs more than ", cloud.dim, " particles");
  std::vector<Vec3> cand;
  if (cloud.dim == 1) {
    std::vector<Real> x;
    for (const auto& p : cloud.positions) x.push_back(p[0]);
    std::sort(x.begin(), x.end());
    for (std::size_t k = 0; k + 1 < x.size(); ++k) cand.emplace_back(0.5 * (x[k] + x[k + 1]), 0, 0);
  } else {
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
  const Real tol = 1e-12 * std::max<Real>(1, estimate_spacing(cloud));
  std::vector<Vec3> inside;
  inside.reserve(cand.size());
  for (auto x : cand) {
    for (int k = cloud.dim; k < 3; ++k) x[k] = 0;
    if (!x.allFinite() || dom.signed_distance(x) < -tol) continue;
    inside.push_back(x);
  }
  std::vector<Real> dist;
  std::vector<Index> idx;
  detail::nearest_particles(cloud, inside, dist, idx);
  CoveringRadius out;
  out.candidates = static_cast<Index>(inside.size());
  for (std::size_t k = 0; k < inside.size(); ++k)
    if (dist[k] > out.radius) {
      out.radius = dist[k];
      out.point = inside[k];
      out.nearest = idx[k];
    }
  return out;
}

}  // namespace vrsph
