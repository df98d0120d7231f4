// SPDX-License-Identifier: BSD-3-Clause
// Measures of Voronoi cells clipped to the domain (see cloud/voronoi.hpp).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>

namespace vrsph {

namespace {

// Half-space {x : n.x <= c}: the side of the bisector of (p, q) that holds p.
struct HalfSpace {
  Vec3 n;
  Real c;
};
HalfSpace bisector(const Vec3& p, const Vec3& q) { return {q - p, 0.5 * (q - p).dot(q + p)}; }

// ---- 2D: a convex polygon cut by half-planes (Sutherland–Hodgman) ----
using FacePolygon = std::vector<Vec3>;

// The part of the convex polygon `poly` on the half-space's side; the points where it
// meets the cutting plane are appended to `on_plane` (if given). Fewer than 3 points: empty.
FacePolygon clip_polygon(const FacePolygon& poly, const HalfSpace& h, FacePolygon* on_plane = nullptr) {
  const Real tol = 1e-14 * (std::abs(h.c) + h.n.norm());
  FacePolygon out;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec3& a = poly[k];
    const Vec3& b = poly[(k + 1) % poly.size()];
    const Real fa = h.n.dot(a) - h.c, fb = h.n.dot(b) - h.c;
    if (fa <= tol) out.push_back(a);
    if (on_plane && std::abs(fa) <= tol) on_plane->push_back(a);
    if ((fa < -tol && fb > tol) || (fa > tol && fb < -tol)) {
      out.push_back(a + (fa / (fa - fb)) * (b - a));
      if (on_plane) on_plane->push_back(out.back());
    }
  }
  return out.size() >= 3 ? out : FacePolygon{};
}

void clip(FacePolygon& poly, const HalfSpace& h) {
  if (!poly.empty()) poly = clip_polygon(poly, h);
}

Real polygon_area(const FacePolygon& p) {
  Real a = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Vec3& u = p[k];
    const Vec3& v = p[(k + 1) % p.size()];
    a += u[0] * v[1] - u[1] * v[0];
  }
  return 0.5 * std::abs(a);
}

// Signed area of the triangle (0, a, b) intersected with the disk |x| < R (Green's theorem
// along the segment: straight parts inside the disk, circular arcs outside).
Real triangle_disk_area(Vec3 a, Vec3 b, Real R) {
  auto arc = [R](const Vec3& u, const Vec3& v) {  // sector between directions u and v
    return 0.5 * R * R * std::atan2(u[0] * v[1] - u[1] * v[0], u.dot(v));
  };
  auto chord = [](const Vec3& u, const Vec3& v) { return 0.5 * (u[0] * v[1] - u[1] * v[0]); };
  const Vec3 d = b - a;
  const Real A = d.squaredNorm(), B = a.dot(d), C = a.squaredNorm() - R * R;
  if (A <= 0) return 0;
  const Real disc = B * B - A * C;
  if (disc <= 0) return arc(a, b);  // the segment's line misses the disk
  const Real s = std::sqrt(disc);
  const Real t0 = std::clamp((-B - s) / A, 0.0, 1.0), t1 = std::clamp((-B + s) / A, 0.0, 1.0);
  const Vec3 p0 = a + t0 * d, p1 = a + t1 * d;
  return arc(a, p0) + chord(p0, p1) + arc(p1, b);
}

Real polygon_disk_area(const FacePolygon& p, const Vec3& centre, Real R) {
  Real a = 0;
  for (std::size_t k = 0; k < p.size(); ++k)
    a += triangle_disk_area(p[k] - centre, p[(k + 1) % p.size()] - centre, R);
  return std::abs(a);
}

// ---- 3D: a convex polyhedron as a list of planar faces, cut by half-spaces ----
using Polyhedron = std::vector<FacePolygon>;

Polyhedron box_polyhedron(const Vec3& lo, const Vec3& hi) {
  auto v = [&](int m) { return Vec3(m & 1 ? hi[0] : lo[0], m & 2 ? hi[1] : lo[1], m & 4 ? hi[2] : lo[2]); };
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  Polyhedron out;
  for (const auto& f : faces) out.push_back({v(f[0]), v(f[1]), v(f[2]), v(f[3])});
  return out;
}

void clip(Polyhedron& poly, const HalfSpace& h) {
  if (poly.empty()) return;
  Polyhedron out;
  FacePolygon cap;  // points on the cutting plane
  for (const auto& face : poly) {
    FacePolygon kept = clip_polygon(face, h, &cap);
    if (!kept.empty()) out.push_back(std::move(kept));
  }
  if (cap.size() >= 3) {  // order the cap's points by angle about their centroid
    Vec3 c = Vec3::Zero();
    for (const auto& p : cap) c += p;
    c /= static_cast<Real>(cap.size());
    const Vec3 n = h.n.normalized();
    const Vec3 e1 = (std::abs(n[0]) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 e2 = n.cross(e1);
    std::sort(cap.begin(), cap.end(), [&](const Vec3& p, const Vec3& q) {
      return std::atan2((p - c).dot(e2), (p - c).dot(e1)) < std::atan2((q - c).dot(e2), (q - c).dot(e1));
    });
    out.push_back(std::move(cap));
  }
  poly = out.size() >= 4 ? std::move(out) : Polyhedron{};
}

// Volume from the faces (each a planar polygon, any orientation): pyramids from an
// interior reference point, each with |height| — valid because the polyhedron is convex.
Real polyhedron_volume(const Polyhedron& poly) {
  if (poly.empty()) return 0;
  Vec3 ref = Vec3::Zero();
  Index count = 0;
  for (const auto& f : poly)
    for (const auto& p : f) ref += p, ++count;
  ref /= static_cast<Real>(count);
  Real vol = 0;
  for (const auto& f : poly) {
    Vec3 area = Vec3::Zero();  // vector area of the face
    for (std::size_t k = 1; k + 1 < f.size(); ++k) area += (f[k] - f[0]).cross(f[k + 1] - f[0]);
    vol += std::abs(area.dot(f[0] - ref)) / 6;
  }
  return vol;
}

std::vector<Real> measures_1d(const PointCloud& cloud) {
  const Domain& dom = cloud.domain;
  const std::size_t n = cloud.positions.size();
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return cloud.positions[a][0] < cloud.positions[b][0]; });
  std::vector<Real> out(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const Real x = cloud.positions[order[k]][0];
    if (k + 1 < n) check<GeometryError>(cloud.positions[order[k + 1]][0] > x, "particles ", std::min(order[k], order[k + 1]),
                                        " and ", std::max(order[k], order[k + 1]), " coincide: their Voronoi cells are undefined");
    const Real left = k == 0 ? dom.lo[0] : std::max(dom.lo[0], 0.5 * (x + cloud.positions[order[k - 1]][0]));
    const Real right = k + 1 == n ? dom.hi[0] : std::min(dom.hi[0], 0.5 * (x + cloud.positions[order[k + 1]][0]));
    out[order[k]] = std::max(Real{0}, right - left);
  }
  return out;
}

// The cells of the first `count` particles, clipped to [lo, hi] (box) or to the disk: their
// measures and, with `reach`, each cell's farthest vertex from its particle (2D/3D).
std::vector<Real> cell_measures(const PointCloud& cloud, Index count, std::vector<Real>* reach) {
  const Domain& dom = cloud.domain;
  const bool box = dom.shape == Domain::Shape::Box;
  const auto nbrs = detail::delaunay_neighbours(cloud);
  const Vec3 lo = box ? dom.lo : Vec3(dom.centre - Vec3(dom.radius, dom.radius, 0));
  const Vec3 hi = box ? dom.hi : Vec3(dom.centre + Vec3(dom.radius, dom.radius, 0));
  std::vector<Real> out(static_cast<std::size_t>(count), 0);
  if (reach) reach->assign(static_cast<std::size_t>(count), 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < count; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& p = cloud.positions[si];
    // Nearest neighbours first: they cut most, so later clips work on small cells.
    auto nb = nbrs[si];
    std::sort(nb.begin(), nb.end(), [&](Index a, Index b) {
      return (cloud.positions[static_cast<std::size_t>(a)] - p).squaredNorm() < (cloud.positions[static_cast<std::size_t>(b)] - p).squaredNorm();
    });
    Real far = 0;
    if (cloud.dim == 2) {
      FacePolygon cell{Vec3(lo[0], lo[1], 0), Vec3(hi[0], lo[1], 0), Vec3(hi[0], hi[1], 0), Vec3(lo[0], hi[1], 0)};
      for (Index j : nb) clip(cell, bisector(p, cloud.positions[static_cast<std::size_t>(j)]));
      out[si] = box ? polygon_area(cell) : polygon_disk_area(cell, dom.centre, dom.radius);
      for (const Vec3& v : cell) far = std::max(far, (v - p).norm());
    } else {
      Polyhedron cell = box_polyhedron(lo, hi);
      for (Index j : nb) clip(cell, bisector(p, cloud.positions[static_cast<std::size_t>(j)]));
      out[si] = polyhedron_volume(cell);
      for (const auto& face : cell)
        for (const Vec3& v : face) far = std::max(far, (v - p).norm());
    }
    if (reach) (*reach)[si] = far;
  }
  return out;
}

// 1D, periodic: each cell is half the gaps on either side, the last gap wrapping around.
std::vector<Real> periodic_measures_1d(const PointCloud& cloud) {
  const Domain& dom = cloud.domain;
  const std::size_t n = cloud.positions.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return cloud.positions[a][0] < cloud.positions[b][0]; });
  std::vector<Real> out(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const Real x = cloud.positions[order[k]][0];
    const Real next = k + 1 < n ? cloud.positions[order[k + 1]][0] : cloud.positions[order[0]][0] + dom.period(0);
    const Real prev = k > 0 ? cloud.positions[order[k - 1]][0] : cloud.positions[order[n - 1]][0] - dom.period(0);
    check<GeometryError>(next > x, "particles ", order[k], " and ", order[(k + 1) % n], " coincide: their Voronoi cells are undefined");
    out[order[k]] = 0.5 * (next - prev);
  }
  return out;
}

// The side of a cube of the box's measure per particle: the length unit of the periodic paths.
Real mean_spacing(const PointCloud& cloud) {
  return std::pow(cloud.domain.measure() / static_cast<Real>(cloud.size()), 1.0 / cloud.dim);
}

bool inside_periodic_axes(const Domain& dom, int dim, const Vec3& x) {
  for (int k = 0; k < dim; ++k)
    if (dom.periodic[static_cast<std::size_t>(k)] && !(x[k] >= dom.lo[k] && x[k] < dom.hi[k])) return false;
  return true;
}

// A box periodic along some axes, every particle inside it: the cells of the periodic
// tessellation, from the cloud extended by its images within w of the periodic faces, clipped to
// the box widened by w along those axes: a computed cell contains the true one (fewer bisectors),
// and a point that could cut it lies within twice its farthest vertex ρ, so the cell is exact
// once 2ρ <= w, every particle within w being there. w starts at 3 spacings and doubles until
// that holds.
std::vector<Real> periodic_measures(const PointCloud& cloud) {
  const Domain& dom = cloud.domain;
  check<InputError>(cloud.size() > cloud.dim, "Voronoi cells need more than ", cloud.dim, " particles");
  if (cloud.dim == 1) return periodic_measures_1d(cloud);
  const Real min_period = dom.shortest_period();
  const Real spacing = mean_spacing(cloud);
  // Images exist for widths below a period (periodic_images); exactness needs 2 ρ <= w.
  const Real cap = (1 - 1e-9) * min_period;
  for (Real width = std::min(3 * spacing, cap);; width = std::min(2 * width, cap)) {
    PeriodicImages extended = periodic_images(cloud, width);
    Domain& box = extended.cloud.domain;
    for (int k = 0; k < cloud.dim; ++k)
      if (box.periodic[static_cast<std::size_t>(k)]) {
        box.lo[k] -= width;
        box.hi[k] += width;
      }
    box.periodic = {false, false, false};
    std::vector<Real> reach;
    std::vector<Real> mine = cell_measures(extended.cloud, cloud.size(), &reach);
    const Real rho = *std::max_element(reach.begin(), reach.end());
    if (2 * rho <= width) return mine;
    check<ConfigError>(width < cap, "a Voronoi cell of this periodic cloud reaches ", rho, " from its particle, over half the period ",
                       min_period, ": too few particles across the box for its cells");
  }
}

// The cells of the cloud's own points, none wrapped: along a periodic axis with particles beyond
// a face the box is widened to hold them (a spacing past the outermost), else clipped there.
std::vector<Real> explicit_point_measures(const PointCloud& cloud) {
  PointCloud plain = cloud;
  Domain& box = plain.domain;
  const Real margin = mean_spacing(cloud);
  for (int k = 0; k < cloud.dim; ++k) {
    if (!box.periodic[static_cast<std::size_t>(k)]) continue;
    Real lo = box.lo[k], hi = box.hi[k];
    for (const Vec3& x : cloud.positions) {
      if (x[k] < box.lo[k]) lo = std::min(lo, x[k] - margin);
      if (x[k] >= box.hi[k]) hi = std::max(hi, x[k] + margin);
    }
    box.lo[k] = lo;
    box.hi[k] = hi;
  }
  box.periodic = {false, false, false};
  return voronoi_cell_measures(plain);
}

}  // namespace

std::vector<Real> voronoi_cell_measures(const PointCloud& cloud, bool whole) {
  validate(cloud);
  const Domain& dom = cloud.domain;
  const bool box = dom.shape == Domain::Shape::Box;
  check<InputError>(box || (dom.shape == Domain::Shape::Ball && cloud.dim == 2),
                    "Voronoi cells are clipped to box domains (1D-3D) and disks only; this cloud's domain is ",
                    dom.shape == Domain::Shape::None ? "unknown" : "a 3D ball");
  if (dom.any_periodic()) {
    bool images = false;  // particles outside the box along a periodic axis: the cloud carries its images
    for (const Vec3& x : cloud.positions) images = images || !inside_periodic_axes(dom, cloud.dim, x);
    return whole && !images ? periodic_measures(cloud) : explicit_point_measures(cloud);
  }
  if (cloud.dim == 1) return measures_1d(cloud);
  check<InputError>(cloud.size() > cloud.dim, "Voronoi cells need more than ", cloud.dim, " particles");
  return cell_measures(cloud, cloud.size(), nullptr);
}

}  // namespace vrsph
