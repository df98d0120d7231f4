// Centroids of a CGAL Delaunay triangulation / tetrahedralisation of a jittered
// node lattice. CGAL is included only here (heavy headers stay out of the library).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "random.hpp"

namespace vrsph {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Jittered node lattice over [lo, hi]: face nodes move only tangentially (so the
// convex hull stays the box), interior nodes by U(-0.15 s, 0.15 s) per coordinate.
std::vector<Vec3> jittered_nodes(int dim, const Vec3& lo, const Vec3& hi, Real s_target, std::uint64_t seed) {
  std::array<int, 3> m{1, 1, 1};
  Vec3 s = Vec3::Zero();
  for (int k = 0; k < dim; ++k) {
    m[static_cast<std::size_t>(k)] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / s_target)));
    s[k] = (hi[k] - lo[k]) / m[static_cast<std::size_t>(k)];
  }
  std::vector<Vec3> nodes;
  std::uint64_t id = 0;
  for (int c = 0; c <= (dim > 2 ? m[2] : 0); ++c)
    for (int b = 0; b <= (dim > 1 ? m[1] : 0); ++b)
      for (int a = 0; a <= m[0]; ++a, ++id) {
        const std::array<int, 3> idx{a, b, c};
        Vec3 x = Vec3::Zero();
        for (int k = 0; k < dim; ++k) {
          const int i = idx[static_cast<std::size_t>(k)];
          x[k] = i == m[static_cast<std::size_t>(k)] ? hi[k] : lo[k] + i * s[k];
          const bool on_face = i == 0 || i == m[static_cast<std::size_t>(k)];
          if (!on_face) x[k] += 0.15 * s[k] * (2 * detail::uniform01(seed, id, static_cast<std::uint64_t>(k)) - 1);
        }
        nodes.push_back(x);
      }
  return nodes;
}

void add_centroid(PointCloud& c, const Domain& box, const Vec3& x) {
  c.positions.push_back(x);
  c.tags.push_back(box.signed_distance(x) >= 0 ? Tag::Interior : Tag::Ghost);
  c.normals.push_back(Vec3::Zero());
}
}  // namespace

PointCloud mesh_centroids(const Domain& box, Real dx, std::uint64_t seed, Real ghost_width, bool boundary_particles,
                          Real* max_edge) {
  check<InputError>(box.shape == Domain::Shape::Box && (box.dim == 2 || box.dim == 3),
                    "mesh centroids need a 2D or 3D box domain");
  check<InputError>(std::isfinite(dx) && dx > 0, "mesh size dx must be positive, got ", dx);
  check<InputError>(ghost_width >= 0, "ghost width must be >= 0");
  check<InputError>(!(boundary_particles && ghost_width > 0), "mesh centroids: boundary particles and ghosts exclude each other");
  const Vec3 lo = box.lo - Vec3::Constant(ghost_width), hi = box.hi + Vec3::Constant(ghost_width);
  Real cells = 1;
  for (int k = 0; k < box.dim; ++k) cells *= (hi[k] - lo[k]) / dx;
  check<InputError>(cells < 5e7, "mesh centroids: dx = ", dx, " gives too many cells");
  const Real s = dx / (box.dim == 2 ? 1.85 : 2.3);
  const auto nodes = jittered_nodes(box.dim, lo, hi, s, seed);
  PointCloud c;
  c.dim = box.dim;
  c.domain = box;
  Real longest = 0;
  if (box.dim == 2) {
    CGAL::Delaunay_triangulation_2<K> dt;
    std::vector<K::Point_2> pts;
    for (const auto& x : nodes) pts.emplace_back(x[0], x[1]);
    dt.insert(pts.begin(), pts.end());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
      const auto a = f->vertex(0)->point(), b = f->vertex(1)->point(), d = f->vertex(2)->point();
      add_centroid(c, box, Vec3((a.x() + b.x() + d.x()) / 3, (a.y() + b.y() + d.y()) / 3, 0));
    }
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e)
      longest = std::max(longest, std::sqrt(CGAL::to_double(dt.segment(*e).squared_length())));
  } else {
    CGAL::Delaunay_triangulation_3<K> dt;
    std::vector<K::Point_3> pts;
    for (const auto& x : nodes) pts.emplace_back(x[0], x[1], x[2]);
    dt.insert(pts.begin(), pts.end());
    for (auto cell = dt.finite_cells_begin(); cell != dt.finite_cells_end(); ++cell) {
      Vec3 g = Vec3::Zero();
      for (int v = 0; v < 4; ++v) {
        const auto p = cell->vertex(v)->point();
        g += Vec3(p.x(), p.y(), p.z());
      }
      add_centroid(c, box, g / 4);
    }
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e)
      longest = std::max(longest, std::sqrt(CGAL::to_double(dt.segment(*e).squared_length())));
  }
  if (boundary_particles)
    for (const auto& x : nodes)
      if (box.signed_distance(x) <= 1e-12 * dx) {
        c.positions.push_back(x);
        c.tags.push_back(Tag::Dirichlet);
        c.normals.push_back(box.outward_normal(x, 1e-12 * dx));
      }
  // Nominal spacing from the particle density inside the box.
  const Index inside = c.size() - c.count(Tag::Ghost);
  c.spacing = std::pow(box.measure() / static_cast<Real>(std::max<Index>(inside, 1)), 1.0 / box.dim);
  if (max_edge) *max_edge = longest;
  return c;
}

}  // namespace vrsph
