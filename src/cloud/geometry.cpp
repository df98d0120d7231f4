// SPDX-License-Identifier: BSD-3-Clause
#include <filesystem>
#include <memory>
#include <vrsph/cloud/geometry.hpp>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>

namespace vrsph {

GeometryCloud fill_geometry(const std::string& path, const GeometryFill& fill) {
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  GeometryCloud g;
  if (ext == ".geojson" || ext == ".json") {
    auto polygon = std::make_shared<Polygon>(read_geojson_polygon(path));
    g.cloud = fill_polygon(*polygon, fill);
    // Edges are sampled finely (cheap in 2D): the covering radius is known to spacing / 16.
    g.sample_step = fill.spacing / 16;
    g.boundary_sample = [polygon, step = g.sample_step] { return sample_polygon_boundary(*polygon, step); };
    g.inside = [polygon](const Vec3& x) { return inside_polygon(*polygon, x); };
  } else if (ext == ".stl" || ext == ".off" || ext == ".obj") {
    auto surface = std::make_shared<ClosedSurface>(read_closed_surface(path));
    g.cloud = fill_surface(*surface, fill);
    g.sample_step = fill.spacing / 4;  // a surface sample grows with step^-2: a quarter spacing
    g.boundary_sample = [surface, step = g.sample_step] { return surface->sample(step); };
    g.inside = [surface](const Vec3& x) { return surface->contains(x); };
  } else {
    throw ConfigError(detail::concat("geometry ", path, ": unknown geometry format '", ext, "' (2D: .geojson or .json, a "
                                     "GeoJSON Polygon or MultiPolygon; 3D: .stl, .off or .obj, a closed surface)"));
  }
  return g;
}

void tag_boundary(PointCloud& cloud, const std::function<bool(const Vec3&)>& neumann_where) {
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    Tag& tag = cloud.tags[i];
    if (tag != Tag::Dirichlet && tag != Tag::Neumann) continue;
    tag = neumann_where(cloud.positions[i]) ? Tag::Neumann : Tag::Dirichlet;
  }
}

}  // namespace vrsph
