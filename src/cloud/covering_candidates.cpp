// SPDX-License-Identifier: BSD-3-Clause
// Candidate maximisers of the nearest-particle distance from the Delaunay structure.
// CGAL stays in this file (compiled in the vrsph_cgal object library).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph::detail {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Points of the line x0 + t u on the domain boundary (box faces or sphere).
void line_hits(const Domain& dom, const Vec3& x0, const Vec3& u, std::vector<Vec3>& out) {
  if (dom.shape == Domain::Shape::None) return;  // a general domain: its boundary is sampled by the caller
  const int d = dom.dim;
  if (dom.shape == Domain::Shape::Box) {
    for (int k = 0; k < d; ++k) {
      if (std::abs(u[k]) < 1e-300) continue;
      for (Real face : {dom.lo[k], dom.hi[k]}) out.push_back(x0 + ((face - x0[k]) / u[k]) * u);
    }
  } else {
    const Vec3 w = x0 - dom.centre;
    const Real a = u.squaredNorm(), b = 2 * w.dot(u), c = w.squaredNorm() - dom.radius * dom.radius;
    const Real disc = b * b - 4 * a * c;
    if (a <= 0 || disc < 0) return;
    const Real s = std::sqrt(disc);
    out.push_back(x0 + ((-b - s) / (2 * a)) * u);
    out.push_back(x0 + ((-b + s) / (2 * a)) * u);
  }
}

// 3D: the bisector plane of (p, q) against the box edges, or against the sphere (the
// point of the plane-sphere circle farthest from p).
void plane_hits(const Domain& dom, const Vec3& p, const Vec3& q, std::vector<Vec3>& out) {
  if (dom.shape == Domain::Shape::None) return;
  const Vec3 nrm = q - p, mid = 0.5 * (p + q);
  if (dom.shape == Domain::Shape::Box) {
    for (int axis = 0; axis < 3; ++axis) {  // edges parallel to `axis`
      if (std::abs(nrm[axis]) < 1e-300) continue;
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      for (Real c1 : {dom.lo[a1], dom.hi[a1]})
        for (Real c2 : {dom.lo[a2], dom.hi[a2]}) {
          Vec3 x;
          x[a1] = c1;
          x[a2] = c2;
          x[axis] = mid[axis] - (nrm[a1] * (c1 - mid[a1]) + nrm[a2] * (c2 - mid[a2])) / nrm[axis];
          out.push_back(x);
        }
    }
  } else {
    const Vec3 n = nrm.normalized();
    const Vec3 c0 = dom.centre - n.dot(dom.centre - mid) * n;  // circle centre
    const Real rho2 = dom.radius * dom.radius - (dom.centre - c0).squaredNorm();
    if (rho2 <= 0) return;
    Vec3 pp = p - n.dot(p - mid) * n - c0;  // p projected into the plane, relative to c0
    if (pp.norm() < 1e-300) return;
    out.push_back(c0 - std::sqrt(rho2) * pp.normalized());
  }
}
}  // namespace

std::vector<Vec3> covering_candidates(const PointCloud& cloud) {
  const Domain& dom = cloud.domain;
  std::vector<Vec3> out;
  if (cloud.dim == 2) {
    CGAL::Delaunay_triangulation_2<K> dt;
    std::vector<K::Point_2> pts;
    for (const auto& x : cloud.positions) pts.emplace_back(x[0], x[1]);
    dt.insert(pts.begin(), pts.end());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
      const auto c = dt.circumcenter(f);
      out.emplace_back(c.x(), c.y(), 0);
    }
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
      const auto s = dt.segment(*e);
      const Vec3 p(s.source().x(), s.source().y(), 0), q(s.target().x(), s.target().y(), 0);
      const Vec3 d = q - p;
      line_hits(dom, 0.5 * (p + q), Vec3(-d[1], d[0], 0), out);  // the bisector line
    }
  } else {
    CGAL::Delaunay_triangulation_3<K> dt;
    std::vector<K::Point_3> pts;
    for (const auto& x : cloud.positions) pts.emplace_back(x[0], x[1], x[2]);
    dt.insert(pts.begin(), pts.end());
    auto vec = [](const K::Point_3& a) { return Vec3(a.x(), a.y(), a.z()); };
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
      out.push_back(vec(CGAL::circumcenter(dt.tetrahedron(c))));
    for (auto f = dt.finite_facets_begin(); f != dt.finite_facets_end(); ++f) {
      const auto t = dt.triangle(*f);
      const Vec3 a = vec(t[0]), b = vec(t[1]), c = vec(t[2]);
      line_hits(dom, vec(CGAL::circumcenter(t[0], t[1], t[2])), (b - a).cross(c - a), out);  // Voronoi edge
    }
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
      const auto s = dt.segment(*e);
      plane_hits(dom, vec(s.source()), vec(s.target()), out);  // Voronoi facet
      plane_hits(dom, vec(s.target()), vec(s.source()), out);
    }
  }
  return out;
}

}  // namespace vrsph::detail
