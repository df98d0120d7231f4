// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// 3D domains bounded by a closed triangle surface, read from STL (ASCII or binary), OFF or
// OBJ (polygon_soup.hpp) and built with CGAL, and filled with particles: boundary particles on the surface (on its
// sharp edges and corners first, then a Poisson-disk set over the faces) with the domain's
// outward unit normals, interior particles on a lattice (optionally perturbed) or as blue
// noise, at least half a spacing inside the surface. CGAL stays in surface.cpp.
#include <memory>
#include <string>
#include <vector>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

class ClosedSurface {
 public:
  ClosedSurface();
  ClosedSurface(ClosedSurface&&) noexcept;
  ClosedSurface& operator=(ClosedSurface&&) noexcept;
  ~ClosedSurface();

  std::size_t triangles() const;
  Real area() const;
  Real volume() const;
  Vec3 lo() const;  ///< bounding box
  Vec3 hi() const;
  /// Inside or on the surface.
  bool contains(const Vec3& x) const;
  /// Distance to the surface.
  Real distance(const Vec3& x) const;
  /// The file's named regions (OBJ groups, the solids of a multi-solid ASCII STL); empty if none.
  const std::vector<std::string>& regions() const;
  /// Whether the surface point x lies on a region whose name contains "neumann" (any case)
  /// and on no other region's face (Dirichlet wins where they meet).
  bool on_neumann_region(const Vec3& x) const;
  /// Points on every face no farther than `step` from any point of the surface (a
  /// barycentric grid per triangle, its vertices included), e.g. to bound the covering radius.
  std::vector<Vec3> sample(Real step) const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  friend ClosedSurface read_closed_surface(const std::string& path);
  std::unique_ptr<Impl> impl_;
};

/// Throws IoError (missing/unreadable file), ConfigError (not .stl/.off/.obj) or InputError
/// naming the file and the problem: what polygon_soup.hpp names, huge coordinates, faces that
/// do not form an orientable manifold, degenerate triangles, not closed
/// (naming how many border edges), self-intersecting (naming two faces), no enclosed volume.
/// Inward-oriented surfaces are reversed.
ClosedSurface read_closed_surface(const std::string& path);

/// Boundary particles tagged Dirichlet, or Neumann on the regions named so (on_neumann_region);
/// interior ones Interior; dim 3, domain shape None,
/// spacing set. Throws ConfigError when the spacing is not positive or too coarse for the
/// solid (fewer than 3 particles across its smallest bounding-box side), ResourceError when
/// the cloud would not fit in memory.
PointCloud fill_surface(const ClosedSurface& surface, const GeometryFill& fill);

}  // namespace vrsph
