// SPDX-License-Identifier: BSD-3-Clause
// Centroids of a CGAL Delaunay triangulation / tetrahedralisation of a jittered node
// lattice, whole or one part of it. CGAL is included only here (heavy headers stay out of
// the library).
//
// Numbering (independent of how many parts make it): the node lattice is cut into layers
// along the last axis (y in 2D, z in 3D); a simplex belongs to the layer of its vertex
// with the smallest node number. Layer by layer: its simplices' centroids, in the order of
// their sorted vertex numbers, then its boundary nodes. A part owns a range of layers and
// triangulates only those nodes and a margin of layers around them; a simplex it keeps is
// the whole mesh's when its circumsphere stays inside the slab where the part has every
// node (checked; the margin grows until it holds), and every simplex of the whole mesh
// owned by the part is in the part's triangulation (an empty sphere stays empty with
// fewer nodes). So the parts are the whole mesh's simplices, bit for bit.
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include "random.hpp"

namespace vrsph {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb2 = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K>;
using Dt2 = CGAL::Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<Vb2>>;
using Vb3 = CGAL::Triangulation_vertex_base_with_info_3<std::size_t, K>;
using Dt3 = CGAL::Delaunay_triangulation_3<K, CGAL::Triangulation_data_structure_3<Vb3>>;

// The jittered node lattice over [lo, hi]: face nodes move only tangentially (so the convex
// hull stays the box), interior nodes by U(-0.15 s, 0.15 s) per coordinate, each from the
// counter-based hash of its number (so any subset of nodes is made alone, identically).
struct NodeLattice {
  int dim = 2;
  std::array<int, 3> m{1, 1, 1};  ///< intervals per axis
  Vec3 lo, hi, s = Vec3::Zero();
  std::uint64_t seed = 1;

  NodeLattice(int d, const Vec3& l, const Vec3& h, Real s_target, std::uint64_t sd) : dim(d), lo(l), hi(h), seed(sd) {
    for (int k = 0; k < dim; ++k) {
      m[static_cast<std::size_t>(k)] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / s_target)));
      s[k] = (hi[k] - lo[k]) / m[static_cast<std::size_t>(k)];
    }
  }
  int layers() const { return m[static_cast<std::size_t>(dim - 1)] + 1; }
  std::size_t per_layer() const { return dim == 2 ? static_cast<std::size_t>(m[0] + 1) : static_cast<std::size_t>(m[0] + 1) * (m[1] + 1); }
  int layer_of(std::size_t id) const { return static_cast<int>(id / per_layer()); }
  Real layer_axis(int layer) const { return lo[dim - 1] + layer * s[dim - 1]; }
  Real jitter() const { return 0.15 * s[dim - 1]; }
  // Node number id = a + (m0 + 1) (b + (m1 + 1) c).
  Vec3 node(std::size_t id) const {
    const std::size_t rest = id / static_cast<std::size_t>(m[0] + 1);
    const std::array<int, 3> i{static_cast<int>(id % static_cast<std::size_t>(m[0] + 1)),
                               static_cast<int>(dim == 2 ? rest : rest % static_cast<std::size_t>(m[1] + 1)),
                               static_cast<int>(dim == 2 ? 0 : rest / static_cast<std::size_t>(m[1] + 1))};
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < dim; ++k) {
      const int ik = i[static_cast<std::size_t>(k)];
      x[k] = ik == m[static_cast<std::size_t>(k)] ? hi[k] : lo[k] + ik * s[k];
      const bool on_face = ik == 0 || ik == m[static_cast<std::size_t>(k)];
      if (!on_face) x[k] += 0.15 * s[k] * (2 * detail::uniform01(seed, id, static_cast<std::uint64_t>(k)) - 1);
    }
    return x;
  }
};

struct Simplex {
  std::array<std::size_t, 4> ids{};  ///< sorted vertex numbers (3 used in 2D)
  Vec3 centroid;
};

struct LayerPart {
  std::vector<Simplex> simplices;  ///< owned, in numbering order
  Real longest = 0;                ///< longest edge of an owned simplex
};

// The simplices owned by layers [l0, l1), from the nodes of layers [l0 - margin, l1 + margin);
// false if some kept simplex's circumsphere leaves the slab where every node is present.
bool owned_simplices(const NodeLattice& lat, int l0, int l1, int margin, LayerPart& out) {
  const int a = std::max(0, l0 - margin), b = std::min(lat.layers(), l1 + margin);
  // The slab that holds every node of the whole lattice: beyond it lie the missing layers.
  const Real inf = std::numeric_limits<Real>::infinity(), slack = 1e-9 * lat.s[lat.dim - 1];
  const Real slab_lo = a == 0 ? -inf : lat.layer_axis(a - 1) + lat.jitter() + slack;
  const Real slab_hi = b == lat.layers() ? inf : lat.layer_axis(b) - lat.jitter() - slack;
  out = {};
  // One simplex of the part's triangulation: kept if its lowest-numbered vertex is in the
  // part's layers; false if it is, but might not be the whole mesh's.
  const auto keep = [&](std::array<std::pair<std::size_t, Vec3>, 4> v, int count, const Vec3& centre) {
    std::sort(v.begin(), v.begin() + count, [](const auto& p, const auto& q) { return p.first < q.first; });
    const int owner = lat.layer_of(v[0].first);
    if (owner < l0 || owner >= l1) return true;
    const Real radius = (centre - v[0].second).norm();
    if (centre[lat.dim - 1] - radius < slab_lo || centre[lat.dim - 1] + radius > slab_hi) return false;
    Simplex sx;
    // The centroid summed in number order: the same whatever the mesh's storage order.
    Vec3 g = Vec3::Zero();
    for (int k = 0; k < count; ++k) {
      sx.ids[static_cast<std::size_t>(k)] = v[static_cast<std::size_t>(k)].first;
      g += v[static_cast<std::size_t>(k)].second;
      for (int l = k + 1; l < count; ++l)
        out.longest = std::max(out.longest, (v[static_cast<std::size_t>(k)].second - v[static_cast<std::size_t>(l)].second).norm());
    }
    sx.centroid = g / count;
    out.simplices.push_back(sx);
    return true;
  };
  const std::size_t first = static_cast<std::size_t>(a) * lat.per_layer(), last = static_cast<std::size_t>(b) * lat.per_layer();
  bool exact = true;
  if (lat.dim == 2) {
    std::vector<std::pair<K::Point_2, std::size_t>> pts;
    for (std::size_t id = first; id < last; ++id) {
      const Vec3 x = lat.node(id);
      pts.emplace_back(K::Point_2(x[0], x[1]), id);
    }
    Dt2 dt(pts.begin(), pts.end());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end() && exact; ++f) {
      std::array<std::pair<std::size_t, Vec3>, 4> v;
      for (int k = 0; k < 3; ++k) {
        const auto p = f->vertex(k)->point();
        v[static_cast<std::size_t>(k)] = {f->vertex(k)->info(), Vec3(p.x(), p.y(), 0)};
      }
      const auto c = CGAL::circumcenter(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      exact = keep(v, 3, Vec3(c.x(), c.y(), 0));
    }
  } else {
    std::vector<std::pair<K::Point_3, std::size_t>> pts;
    for (std::size_t id = first; id < last; ++id) {
      const Vec3 x = lat.node(id);
      pts.emplace_back(K::Point_3(x[0], x[1], x[2]), id);
    }
    Dt3 dt(pts.begin(), pts.end());
    for (auto cell = dt.finite_cells_begin(); cell != dt.finite_cells_end() && exact; ++cell) {
      std::array<std::pair<std::size_t, Vec3>, 4> v;
      for (int k = 0; k < 4; ++k) {
        const auto p = cell->vertex(k)->point();
        v[static_cast<std::size_t>(k)] = {cell->vertex(k)->info(), Vec3(p.x(), p.y(), p.z())};
      }
      const auto c = CGAL::circumcenter(cell->vertex(0)->point(), cell->vertex(1)->point(), cell->vertex(2)->point(),
                                        cell->vertex(3)->point());
      exact = keep(v, 4, Vec3(c.x(), c.y(), c.z()));
    }
  }
  if (!exact) return false;
  std::sort(out.simplices.begin(), out.simplices.end(), [](const Simplex& p, const Simplex& q) { return p.ids < q.ids; });
  return true;
}
}  // namespace

MeshCentroidsPart mesh_centroids_part(const Domain& box, Real dx, std::uint64_t seed, Real ghost_width,
                                      bool boundary_particles, int part, int parts) {
  check<InputError>(box.shape == Domain::Shape::Box && (box.dim == 2 || box.dim == 3),
                    "mesh centroids need a 2D or 3D box domain");
  check<InputError>(std::isfinite(dx) && dx > 0, "mesh size dx must be positive, got ", dx);
  check<InputError>(ghost_width >= 0, "ghost width must be >= 0");
  check<InputError>(!(boundary_particles && ghost_width > 0), "mesh centroids: boundary particles and ghosts exclude each other");
  check<ConfigError>(parts >= 1 && part >= 0 && part < parts, "mesh centroids: part ", part, " of ", parts);
  const Vec3 lo = box.lo - Vec3::Constant(ghost_width), hi = box.hi + Vec3::Constant(ghost_width);
  Real cells = 1;
  for (int k = 0; k < box.dim; ++k) cells *= (hi[k] - lo[k]) / dx;
  check<InputError>(cells < 5e7, "mesh centroids: dx = ", dx, " gives too many cells");
  const NodeLattice lat(box.dim, lo, hi, dx / (box.dim == 2 ? 1.85 : 2.3), seed);
  const auto layer_bound = [&](int p) { return static_cast<int>(static_cast<long long>(lat.layers()) * p / parts); };
  const int l0 = layer_bound(part), l1 = layer_bound(part + 1);
  MeshCentroidsPart out;
  PointCloud& c = out.cloud;
  c.dim = box.dim;
  c.domain = box;
  LayerPart mine;
  for (int margin = 3; l0 < l1 && !owned_simplices(lat, l0, l1, margin, mine); margin *= 2) {
  }
  out.max_edge = mine.longest;
  // Layer by layer: its simplices' centroids, then its boundary nodes.
  std::size_t next = 0;
  for (int layer = l0; layer < l1; ++layer) {
    for (; next < mine.simplices.size() && lat.layer_of(mine.simplices[next].ids[0]) == layer; ++next) {
      const Vec3& x = mine.simplices[next].centroid;
      c.positions.push_back(x);
      c.tags.push_back(box.signed_distance(x) >= 0 ? Tag::Interior : Tag::Ghost);
      c.normals.push_back(Vec3::Zero());
    }
    if (!boundary_particles) continue;
    for (std::size_t id = static_cast<std::size_t>(layer) * lat.per_layer(); id < static_cast<std::size_t>(layer + 1) * lat.per_layer(); ++id) {
      const Vec3 x = lat.node(id);
      if (box.signed_distance(x) > 1e-12 * dx) continue;
      c.positions.push_back(x);
      c.tags.push_back(Tag::Dirichlet);
      c.normals.push_back(box.outward_normal(x, 1e-12 * dx));
    }
  }
  out.inside = c.size() - c.count(Tag::Ghost);
  return out;
}

PointCloud mesh_centroids(const Domain& box, Real dx, std::uint64_t seed, Real ghost_width, bool boundary_particles,
                          Real* max_edge) {
  MeshCentroidsPart whole = mesh_centroids_part(box, dx, seed, ghost_width, boundary_particles, 0, 1);
  // Nominal spacing from the particle density inside the box.
  whole.cloud.spacing = std::pow(box.measure() / static_cast<Real>(std::max<Index>(whole.inside, 1)), 1.0 / box.dim);
  if (max_edge) *max_edge = whole.max_edge;
  return std::move(whole.cloud);
}

}  // namespace vrsph
