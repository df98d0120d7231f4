#include <algorithm>
#include <cmath>
#include <optional>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

namespace detail {
// Nearest particle of each query point (k-d tree); defined in neighbours/kd_tree.cpp.
void nearest_particles(const PointCloud& cloud, const std::vector<Vec3>& queries, std::vector<Real>& dist,
                       std::vector<Index>& index);
}  // namespace detail

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
  return farthest_candidate(cloud, inside);
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
