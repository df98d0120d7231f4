// SPDX-License-Identifier: BSD-3-Clause
// Delaunay adjacency of a 2D/3D cloud. CGAL stays in this file (vrsph_cgal object library).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <algorithm>
#include <numeric>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph::detail {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// CGAL keeps one vertex per position: name a coincident pair when vertices went missing.
[[noreturn]] void throw_coincident(const PointCloud& cloud) {
  std::vector<Index> order(static_cast<std::size_t>(cloud.size()));
  std::iota(order.begin(), order.end(), Index{0});
  const auto& x = cloud.positions;
  auto key = [&](Index i) { const auto& p = x[static_cast<std::size_t>(i)]; return std::array<Real, 3>{p[0], p[1], p[2]}; };
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return key(a) < key(b); });
  for (std::size_t k = 0; k + 1 < order.size(); ++k)
    if (key(order[k]) == key(order[k + 1]))
      throw GeometryError(concat("particles ", std::min(order[k], order[k + 1]), " and ", std::max(order[k], order[k + 1]),
                                 " coincide: their Voronoi cells are undefined"));
  throw GeometryError("the Delaunay triangulation lost particles (coincident points)");
}

template <class Dt, class Point, int Dim>
std::vector<std::vector<Index>> adjacency(const PointCloud& cloud, auto make_point) {
  std::vector<std::pair<Point, Index>> pts;
  pts.reserve(cloud.positions.size());
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) pts.emplace_back(make_point(cloud.positions[i]), static_cast<Index>(i));
  Dt dt(pts.begin(), pts.end());
  if (static_cast<Index>(dt.number_of_vertices()) != cloud.size()) throw_coincident(cloud);
  std::vector<std::vector<Index>> out(static_cast<std::size_t>(cloud.size()));
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    Index a, b;
    if constexpr (Dim == 2) {
      a = e->first->vertex(Dt::cw(e->second))->info();
      b = e->first->vertex(Dt::ccw(e->second))->info();
    } else {
      a = e->first->vertex(e->second)->info();
      b = e->first->vertex(e->third)->info();
    }
    out[static_cast<std::size_t>(a)].push_back(b);
    out[static_cast<std::size_t>(b)].push_back(a);
  }
  return out;
}
}  // namespace

std::vector<std::vector<Index>> delaunay_neighbours(const PointCloud& cloud) {
  if (cloud.dim == 2) {
    using Vb = CGAL::Triangulation_vertex_base_with_info_2<Index, K>;
    using Dt = CGAL::Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<Vb>>;
    return adjacency<Dt, K::Point_2, 2>(cloud, [](const Vec3& p) { return K::Point_2(p[0], p[1]); });
  }
  check<InputError>(cloud.dim == 3, "Delaunay neighbours need a 2D or 3D cloud");
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<Index, K>;
  using Dt = CGAL::Delaunay_triangulation_3<K, CGAL::Triangulation_data_structure_3<Vb>>;
  return adjacency<Dt, K::Point_3, 3>(cloud, [](const Vec3& p) { return K::Point_3(p[0], p[1], p[2]); });
}

}  // namespace vrsph::detail
