// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A geometry file (2D polygon or 3D closed surface, chosen by the extension) filled with
// particles in one call, with what the covering radius of the result needs: the domain's
// membership test and a sample of its boundary.
#include <functional>
#include <string>
#include <vector>
#include <vrsph/cloud/geometry_fill.hpp>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct GeometryCloud {
  PointCloud cloud;                          ///< boundary particles Dirichlet (see tag_boundary)
  std::function<bool(const Vec3&)> inside;   ///< the domain (closed)
  /// Points with every boundary point within sample_step of one of them; computed on call
  /// (only the covering radius needs them, and a fine surface gives millions).
  std::function<std::vector<Vec3>()> boundary_sample;
  Real sample_step = 0;
};

/// .geojson / .json: a GeoJSON polygon (polygon.hpp); .stl / .off / .obj: a closed
/// surface (surface.hpp). Throws ConfigError for another extension, and what the readers and
/// fills throw.
GeometryCloud fill_geometry(const std::string& path, const GeometryFill& fill);

/// Boundary (Dirichlet or Neumann) particles become Neumann where neumann_where(x) holds and
/// Dirichlet elsewhere; interior and ghost particles are left alone.
void tag_boundary(PointCloud& cloud, const std::function<bool(const Vec3&)>& neumann_where);

}  // namespace vrsph
