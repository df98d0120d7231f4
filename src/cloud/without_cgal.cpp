// SPDX-License-Identifier: BSD-3-Clause
// A build without CGAL (VRSPH_WITH_CGAL=OFF): what CGAL computes in mesh_centroids.cpp,
// covering_candidates.cpp, surface.cpp and delaunay_neighbours.cpp is refused with
// FeatureUnavailable, naming the feature the user asked for.
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/cloud/voronoi.hpp>
#include <vrsph/core/features.hpp>

namespace vrsph {

namespace {
[[noreturn]] void without_cgal(const char* feature) {
  require_part("CGAL", feature);
  throw FeatureUnavailable(feature);  // not reached: the part is not built
}
constexpr const char* kSurface = "a closed surface (STL/OFF/OBJ solid)";
}  // namespace

PointCloud mesh_centroids(const Domain&, Real, std::uint64_t, Real, bool, Real*) {
  without_cgal("the mesh-centroid cloud (a Delaunay mesh of the box)");
}
MeshCentroidsPart mesh_centroids_part(const Domain&, Real, std::uint64_t, Real, bool, int, int) {
  without_cgal("the mesh-centroid cloud (a Delaunay mesh of the box)");
}

struct ClosedSurface::Impl {};
ClosedSurface::ClosedSurface() : impl_(std::make_unique<Impl>()) {}
ClosedSurface::ClosedSurface(ClosedSurface&&) noexcept = default;
ClosedSurface& ClosedSurface::operator=(ClosedSurface&&) noexcept = default;
ClosedSurface::~ClosedSurface() = default;
std::size_t ClosedSurface::triangles() const { without_cgal(kSurface); }
Real ClosedSurface::area() const { without_cgal(kSurface); }
Real ClosedSurface::volume() const { without_cgal(kSurface); }
Vec3 ClosedSurface::lo() const { without_cgal(kSurface); }
Vec3 ClosedSurface::hi() const { without_cgal(kSurface); }
bool ClosedSurface::contains(const Vec3&) const { without_cgal(kSurface); }
Real ClosedSurface::distance(const Vec3&) const { without_cgal(kSurface); }
const std::vector<std::string>& ClosedSurface::regions() const { without_cgal(kSurface); }
bool ClosedSurface::on_neumann_region(const Vec3&) const { without_cgal(kSurface); }
std::vector<Vec3> ClosedSurface::sample(Real) const { without_cgal(kSurface); }
ClosedSurface read_closed_surface(const std::string&) { without_cgal(kSurface); }
PointCloud fill_surface(const ClosedSurface&, const GeometryFill&) { without_cgal(kSurface); }

namespace detail {
std::vector<Vec3> covering_candidates(const PointCloud&) {
  without_cgal("the covering radius in 2D/3D (Voronoi vertices)");
}
std::vector<std::vector<Index>> delaunay_neighbours(const PointCloud&) {
  without_cgal("Delaunay neighbours (Voronoi cell measures)");
}
}  // namespace detail

}  // namespace vrsph
