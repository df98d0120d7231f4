// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/io/input_file.hpp>
#include "interior_fill.hpp"
#include "polygon_checks.hpp"

namespace vrsph {

namespace {
Real cross(const Vec3& a, const Vec3& b) { return a[0] * b[1] - a[1] * b[0]; }

// Whether segments pq and rs intersect (touching included).
bool segments_meet(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  const auto orient = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    const Real v = cross(b - a, c - a);
    return (v > 0) - (v < 0);
  };
  const auto on = [](const Vec3& a, const Vec3& b, const Vec3& c) {  // c on segment ab, given collinear
    return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
           c[1] <= std::max(a[1], b[1]);
  };
  const int o1 = orient(p, q, r), o2 = orient(p, q, s), o3 = orient(r, s, p), o4 = orient(r, s, q);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && on(p, q, r)) || (o2 == 0 && on(p, q, s)) || (o3 == 0 && on(r, s, p)) || (o4 == 0 && on(r, s, q));
}

Real signed_area(const std::vector<Vec3>& ring) {
  Real a = 0;
  for (std::size_t k = 0; k < ring.size(); ++k) a += cross(ring[k], ring[(k + 1) % ring.size()]);
  return a / 2;
}

bool inside_ring(const std::vector<Vec3>& ring, const Vec3& x) {  // even-odd rule
  bool in = false;
  for (std::size_t k = 0, j = ring.size() - 1; k < ring.size(); j = k++) {
    const Vec3 &a = ring[k], &b = ring[j];
    if ((a[1] > x[1]) != (b[1] > x[1]) && x[0] < (b[0] - a[0]) * (x[1] - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
  }
  return in;
}

Real distance_to_segment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), Real(0), Real(1));
  return (x - (a + t * ab)).norm();
}

}  // namespace

namespace detail {
// part_of[r]: the MultiPolygon part ring r belongs to; first_ring[r]: that part's outer ring.
void check_polygon(const Polygon& p, const std::vector<std::size_t>& part_of, const std::vector<std::size_t>& first_ring,
                   const std::string& name) {
  for (std::size_t r = 0; r < p.rings.size(); ++r) {
    const auto& ring = p.rings[r];
    check<InputError>(ring.size() >= 3, name, ": ring ", r, " has ", ring.size(), " distinct vertices (at least 3 needed)");
    check<InputError>(std::abs(signed_area(ring)) > 0, name, ": ring ", r, " encloses no area");
  }
  // Every pair of edges that are not neighbours on one ring must not meet.
  for (std::size_t r1 = 0; r1 < p.rings.size(); ++r1)
    for (std::size_t e1 = 0; e1 < p.rings[r1].size(); ++e1)
      for (std::size_t r2 = r1; r2 < p.rings.size(); ++r2)
        for (std::size_t e2 = r1 == r2 ? e1 + 1 : 0; e2 < p.rings[r2].size(); ++e2) {
          const std::size_t n = p.rings[r1].size();
          if (r1 == r2 && (e2 == e1 + 1 || (e1 == 0 && e2 == n - 1))) continue;  // share a vertex
          const auto& a = p.rings[r1];
          const auto& b = p.rings[r2];
          check<InputError>(!segments_meet(a[e1], a[(e1 + 1) % a.size()], b[e2], b[(e2 + 1) % b.size()]), name,
                            ": edges cross or touch: ring ", r1, " edge ", e1, " and ring ", r2, " edge ", e2,
                            " (the polygon must be simple, its holes inside it and apart)");
        }
  // Each hole inside its own polygon's outer ring; each part's outer ring in no other part's
  // solid region (it may sit in a hole of another part: an island). Rings do not meet, so one
  // vertex decides whether a ring lies inside another.
  const std::vector<int> depth = ring_depths(p);
  for (std::size_t r = 0; r < p.rings.size(); ++r) {
    const std::size_t outer = first_ring[r];
    if (r != outer)
      check<InputError>(inside_ring(p.rings[outer], p.rings[r][0]), name, ": hole ", r - outer, " of polygon ",
                        part_of[r], " lies outside its outer ring");
    else
      check<InputError>(depth[r] % 2 == 0, name, ": polygon ", part_of[r], " of the MultiPolygon lies inside another ",
                        "polygon's area (its parts must lie apart, or inside one another's holes)");
  }
}
}  // namespace detail

Polygon read_geojson_polygon(const std::string& path) {
  return parse_geojson_polygon(read_file(path, "geometry file"), path);
}

bool inside_polygon(const Polygon& polygon, const Vec3& x) {
  bool in = false;
  for (const auto& ring : polygon.rings) in = in != inside_ring(ring, x);
  return in;
}

std::vector<int> ring_depths(const Polygon& polygon) {
  std::vector<int> depth(polygon.rings.size(), 0);
  for (std::size_t r = 0; r < polygon.rings.size(); ++r)
    for (std::size_t q = 0; q < polygon.rings.size(); ++q)
      depth[r] += q != r && inside_ring(polygon.rings[q], polygon.rings[r][0]);
  return depth;
}

Real distance_to_polygon_boundary(const Polygon& polygon, const Vec3& x) {
  Real d = std::numeric_limits<Real>::infinity();
  for (const auto& ring : polygon.rings)
    for (std::size_t e = 0; e < ring.size(); ++e) d = std::min(d, distance_to_segment(x, ring[e], ring[(e + 1) % ring.size()]));
  return d;
}

std::vector<Vec3> sample_polygon_boundary(const Polygon& polygon, Real step) {
  check<ConfigError>(std::isfinite(step) && step > 0, "boundary sampling step must be positive, got ", step);
  std::vector<Vec3> out;
  for (const auto& ring : polygon.rings)
    for (std::size_t e = 0; e < ring.size(); ++e) {
      const Vec3 a = ring[e], b = ring[(e + 1) % ring.size()];
      const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
      for (int k = 0; k < pieces; ++k) out.push_back(a + (b - a) * (static_cast<Real>(k) / pieces));
    }
  return out;
}

PointCloud fill_polygon(const Polygon& p, const PolygonFill& f) {
  check<ConfigError>(std::isfinite(f.spacing) && f.spacing > 0, "the spacing must be positive and finite, got ", f.spacing);
  check<ConfigError>(std::isfinite(f.delta) && f.delta >= 0 && f.delta < 0.5, "the perturbation must be in [0, 0.5), got ",
                     f.delta);
  Real smallest = std::numeric_limits<Real>::infinity();
  Vec3 lo = p.rings[0][0], hi = p.rings[0][0];
  for (const auto& ring : p.rings) {
    Vec3 rlo = ring[0], rhi = ring[0];
    for (const Vec3& x : ring) {
      rlo = rlo.cwiseMin(x);
      rhi = rhi.cwiseMax(x);
    }
    smallest = std::min(smallest, (rhi - rlo).head<2>().maxCoeff());
    lo = lo.cwiseMin(rlo);
    hi = hi.cwiseMax(rhi);
  }
  check<ConfigError>(f.spacing * 3 <= smallest, "the spacing ", f.spacing, " is too large for the geometry: its smallest ",
                     "ring spans ", smallest, " (at least 3 particles across are needed)");
  const double lattice = ((hi[0] - lo[0]) / f.spacing + 1) * ((hi[1] - lo[1]) / f.spacing + 1);
  detail::check_lattice_size(lattice, f.spacing);
  check_memory_estimate(lattice / f.parts * (2 * sizeof(Vec3) + sizeof(Tag)),
                        detail::concat("the cloud of the geometry (up to ", lattice, " particles)"),
                        "choose a larger --spacing");
  PointCloud c;
  c.dim = 2;
  c.spacing = f.spacing;
  // Every particle carries a normal (zero inside): PointCloud::add keeps normals only once
  // the cloud has them.
  const auto put = [&c](const Vec3& x, Tag t, const Vec3& n) {
    c.positions.push_back(x);
    c.tags.push_back(t);
    c.normals.push_back(n);
  };
  // Boundary: each edge split into ceil(length / spacing) pieces; the outward normal of the
  // domain is the ring's outward normal for rings at even depth (outer rings, islands) and its
  // inward one for holes.
  const std::vector<int> depth = ring_depths(p);
  for (std::size_t r = 0; r < p.rings.size() && f.part == 0; ++r) {  // (a part > 0: interior layers only)
    const auto& ring = p.rings[r];
    const Real orientation = signed_area(ring) > 0 ? 1 : -1;  // +1: counter-clockwise
    const Real side = (depth[r] % 2 == 0 ? 1 : -1) * orientation;
    const std::size_t n = ring.size();
    auto edge_normal = [&](std::size_t e) {
      const Vec3 d = ring[(e + 1) % n] - ring[e];
      return Vec3(side * d[1], -side * d[0], 0).normalized();  // right of d for a CCW outer ring
    };
    for (std::size_t e = 0; e < n; ++e) {
      const Vec3 a = ring[e], b = ring[(e + 1) % n];
      const auto pieces = static_cast<int>(std::ceil((b - a).norm() / f.spacing - 1e-9));
      const Vec3 vertex_normal = (edge_normal((e + n - 1) % n) + edge_normal(e)).normalized();
      put(a, Tag::Dirichlet, vertex_normal);
      for (int k = 1; k < pieces; ++k) put(a + (b - a) * (static_cast<Real>(k) / pieces), Tag::Dirichlet, edge_normal(e));
    }
  }
  // Interior: at least half a spacing from every edge; a lattice, or blue noise grown from
  // the boundary particles.
  const auto admissible = [&](const Vec3& x) {
    return inside_polygon(p, x) && distance_to_polygon_boundary(p, x) >= 0.5 * f.spacing;
  };
  detail::add_interior_particles(c, lo, hi, f, f.seed, admissible);
  // A sliver or needle can span many spacings and still be thinner than one: no particle is
  // half a spacing from every edge, and the "domain" would be its boundary alone.
  check<ConfigError>(f.parts > 1 || c.count(Tag::Interior) > 0, "the geometry leaves no room for interior particles at ",
                     "the spacing ", f.spacing, " (it is thinner than about one spacing); choose a smaller --spacing");
  if (c.size() > 0 || f.parts == 1) validate(c);  // (a part may be empty)
  return c;
}

}  // namespace vrsph
