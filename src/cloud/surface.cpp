// SPDX-License-Identifier: BSD-3-Clause
// Closed triangle surfaces (CGAL Surface_mesh, AABB tree, Side_of_triangle_mesh) built from
// the polygon soups of polygon_soup.cpp, and their particle fill. CGAL stays in this file
// (compiled in the vrsph_cgal object library).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vrsph/cloud/blue_noise.hpp>
#include <vrsph/cloud/polygon_soup.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/resources.hpp>
#include "interior_fill.hpp"
#include "random.hpp"

namespace vrsph {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
using Triangles = std::vector<K::Triangle_3>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;

struct ClosedSurface::Impl {
  Mesh mesh;
  std::optional<Tree> tree;
  std::optional<CGAL::Side_of_triangle_mesh<Mesh, K>> side;
  std::vector<Vec3> face_normal;  ///< outward unit normal per face index
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  Real area = 0, volume = 0;
  // Named regions (OBJ groups, STL solids): the triangles of the regions whose name does not
  // say "neumann", searched when some region does (see fill_surface).
  std::vector<std::string> regions;
  bool has_neumann_region = false;
  Triangles dirichlet_triangles;
  std::optional<TriangleTree> dirichlet_tree;
  // Everything above is in the surface's own frame, x̂ = (x - origin) / unit with unit the
  // largest side of the bounding box: CGAL's predicates (the inside test's ray shooting
  // fell back to exact arithmetic for ever at 1e20) and every tolerance see O(1) numbers,
  // whatever the file's length unit. The public methods take and give file coordinates.
  Vec3 origin = Vec3::Zero();
  Real unit = 1;
  Vec3 to_frame(const Vec3& x) const { return (x - origin) / unit; }
  Vec3 from_frame(const Vec3& x) const { return origin + unit * x; }
};

namespace {
Vec3 vec(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }
K::Point_3 point(const Vec3& x) { return {x[0], x[1], x[2]}; }

std::array<Vec3, 3> corners(const Mesh& m, Mesh::Face_index f) {
  std::array<Vec3, 3> out;
  int k = 0;
  for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) out[static_cast<std::size_t>(k++)] = vec(m.point(v));
  return out;
}

// Interior angle of face f at its corner v.
Real corner_angle(const Mesh& m, Mesh::Halfedge_index h) {
  const Vec3 v = vec(m.point(m.target(h)));
  const Vec3 a = vec(m.point(m.source(h))) - v, b = vec(m.point(m.target(m.next(h)))) - v;
  return std::atan2(a.cross(b).norm(), a.dot(b));
}
}  // namespace

ClosedSurface::ClosedSurface() : impl_(std::make_unique<Impl>()) {}
ClosedSurface::ClosedSurface(ClosedSurface&&) noexcept = default;
ClosedSurface& ClosedSurface::operator=(ClosedSurface&&) noexcept = default;
ClosedSurface::~ClosedSurface() = default;

namespace {
// The queries in the surface's own frame (fill_surface works in it throughout).
bool contains_in_frame(const ClosedSurface::Impl& impl, const Vec3& x) {
  return (*impl.side)(point(x)) != CGAL::ON_UNBOUNDED_SIDE;
}
Real distance_in_frame(const ClosedSurface::Impl& impl, const Vec3& x) {
  return std::sqrt(impl.tree->squared_distance(point(x)));
}
bool on_neumann_region_in_frame(const ClosedSurface::Impl& impl, const Vec3& x) {
  if (!impl.has_neumann_region) return false;
  if (!impl.dirichlet_tree) return true;  // every region is Neumann
  // On a Dirichlet region's face (to round-off): Dirichlet, also where it meets a Neumann one.
  const Real tol = 1e-9 * (impl.hi - impl.lo).norm();
  return impl.dirichlet_tree->squared_distance(point(x)) > tol * tol;
}
}  // namespace

std::size_t ClosedSurface::triangles() const { return impl_->mesh.number_of_faces(); }
Real ClosedSurface::area() const { return impl_->area * impl_->unit * impl_->unit; }
Real ClosedSurface::volume() const { return impl_->volume * impl_->unit * impl_->unit * impl_->unit; }
Vec3 ClosedSurface::lo() const { return impl_->from_frame(impl_->lo); }
Vec3 ClosedSurface::hi() const { return impl_->from_frame(impl_->hi); }
bool ClosedSurface::contains(const Vec3& x) const { return contains_in_frame(*impl_, impl_->to_frame(x)); }
Real ClosedSurface::distance(const Vec3& x) const { return impl_->unit * distance_in_frame(*impl_, impl_->to_frame(x)); }
const std::vector<std::string>& ClosedSurface::regions() const { return impl_->regions; }

bool ClosedSurface::on_neumann_region(const Vec3& x) const {
  return on_neumann_region_in_frame(*impl_, impl_->to_frame(x));
}

std::vector<Vec3> ClosedSurface::sample(Real step) const {
  check<ConfigError>(std::isfinite(step) && step > 0, "surface sampling step must be positive, got ", step);
  step /= impl_->unit;
  std::vector<Vec3> out;
  for (auto f : impl_->mesh.faces()) {
    const auto c = corners(impl_->mesh, f);
    const Real longest = std::max({(c[1] - c[0]).norm(), (c[2] - c[1]).norm(), (c[0] - c[2]).norm()});
    // A grid of m x m subdivisions: sub-triangles have sides <= longest / m <= step, so every
    // point of the face is within step of a grid point.
    const int m = std::max(1, static_cast<int>(std::ceil(longest / step)));
    for (int i = 0; i <= m; ++i)
      for (int j = 0; i + j <= m; ++j) {
        const Real a = static_cast<Real>(i) / m, b = static_cast<Real>(j) / m;
        out.push_back(impl_->from_frame(c[0] + a * (c[1] - c[0]) + b * (c[2] - c[0])));
      }
  }
  return out;
}

namespace {
// Whether a polygonal face encloses no area (its Newell normal vanishes).
bool zero_area(const std::vector<K::Point_3>& points, const std::vector<std::size_t>& face) {
  Vec3 normal = Vec3::Zero();
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Vec3 a = vec(points[face[k]]), b = vec(points[face[(k + 1) % face.size()]]);
    normal += a.cross(b);
  }
  Real scale = 0;
  for (const std::size_t v : face) scale = std::max(scale, vec(points[v]).squaredNorm());
  return normal.norm() <= 1e-14 * scale;
}
}  // namespace

namespace {
using SurfaceImpl = ClosedSurface::Impl;

// The surface's own frame (see Impl): its bounding box's corner at the origin, its longest
// side the unit.
void to_surface_frame(PolygonSoup& soup, SurfaceImpl& impl) {
  if (soup.points.empty()) return;
  Vec3 lo = soup.points.front(), hi = lo;
  for (const Vec3& x : soup.points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  impl.origin = lo;
  const Real side = (hi - lo).maxCoeff();
  impl.unit = side > 0 && std::isfinite(side) ? side : 1;
  for (Vec3& x : soup.points) x = impl.to_frame(x);
}

// With a region named "neumann": the other regions' faces, fan-triangulated, for the tag
// of boundary particles.
void dirichlet_regions(const PolygonSoup& soup, const std::vector<K::Point_3>& points, SurfaceImpl& impl) {
  impl.regions = soup.regions;
  for (const auto& name : soup.regions) impl.has_neumann_region |= to_lower(name).find("neumann") != std::string::npos;
  if (!impl.has_neumann_region) return;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (to_lower(soup.regions[soup.face_region[f]]).find("neumann") != std::string::npos) continue;
    const auto& face = soup.faces[f];
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const K::Triangle_3 t(points[face[0]], points[face[k]], points[face[k + 1]]);
      if (!t.is_degenerate()) impl.dirichlet_triangles.push_back(t);  // no area: nothing to be near
    }
  }
  if (impl.dirichlet_triangles.empty()) return;
  impl.dirichlet_tree.emplace(impl.dirichlet_triangles.begin(), impl.dirichlet_triangles.end());
  impl.dirichlet_tree->accelerate_distance_queries();
}

// Duplicate points merged, degenerate and repeated faces dropped, faces oriented consistently.
void repair_and_orient(const std::string& path, std::vector<K::Point_3>& points, std::vector<std::vector<std::size_t>>& faces) {
  PMP::repair_polygon_soup(points, faces);
  check<InputError>(!faces.empty(), path, ": every face is degenerate (no area)");
  // A face of zero area (collinear vertices) lying on a closed surface shares its edges with
  // faces that already meet in pairs, so the soup cannot be oriented. Such a face carries no
  // surface: without it the rest may be a closed, orientable surface, and is taken as one.
  std::vector<K::Point_3> kept_points = points;
  std::vector<std::vector<std::size_t>> kept_faces = faces;
  if (!PMP::orient_polygon_soup(points, faces)) {
    const std::size_t before = kept_faces.size();
    std::erase_if(kept_faces, [&](const std::vector<std::size_t>& face) { return zero_area(kept_points, face); });
    const std::size_t dropped = before - kept_faces.size();
    points = std::move(kept_points);
    faces = std::move(kept_faces);
    check<InputError>(dropped > 0 && !faces.empty() && PMP::orient_polygon_soup(points, faces), path,
                      ": the faces do not form an orientable manifold surface (an edge shared by more than two faces, "
                      "or faces that cannot be oriented alike)",
                      dropped > 0 ? detail::concat(", also without its ", dropped, " face(s) of zero area") : "");
  }
  // Points no face uses any more (a dropped face's) would be isolated vertices, which the
  // orientation of the shells below does not accept.
  PMP::remove_isolated_points_in_polygon_soup(points, faces);
}

// A triangle mesh, closed, without degenerate faces or self-intersections.
void check_closed_mesh(const std::string& path, Mesh& m) {
  check<InputError>(m.number_of_faces() > 0, path, ": no faces left after repair");
  if (!CGAL::is_triangle_mesh(m))
    check<InputError>(PMP::triangulate_faces(m), path, ": a polygonal face could not be split into triangles");
  for (auto f : m.faces())
    check<InputError>(!PMP::is_degenerate_triangle_face(f, m), path, ": face ", static_cast<std::size_t>(f),
                      " is degenerate (zero area)");
  std::size_t border = 0;
  for (auto h : m.halfedges()) border += m.is_border(h) ? 1 : 0;
  check<InputError>(border == 0, path, ": the surface is not closed (", border, " border edges); a solid needs a "
                    "watertight surface");
  if (!PMP::does_self_intersect(m)) return;
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  PMP::self_intersections(m, std::back_inserter(pairs));
  const auto f1 = pairs.empty() ? 0u : static_cast<std::size_t>(pairs.front().first),
             f2 = pairs.empty() ? 0u : static_cast<std::size_t>(pairs.front().second);
  throw InputError(detail::concat(path, ": the surface intersects itself (", pairs.size(), " face pairs, e.g. faces ",
                                  f1, " and ", f2, ")"));
}

// Every shell oriented by its nesting: an outer shell's normals point out, a cavity's into
// the cavity (out of the material), whichever way the file stored each solid. Then the
// volume, area, face normals, bounding box and the search trees.
void finish_surface(const std::string& path, SurfaceImpl& impl) {
  Mesh& m = impl.mesh;
  PMP::orient_to_bound_a_volume(m);
  impl.volume = PMP::volume(m);
  impl.area = PMP::area(m);
  check<InputError>(impl.volume > 0 && std::isfinite(impl.volume), path, ": the surface encloses no volume");
  impl.face_normal.assign(m.number_of_faces(), Vec3::Zero());
  for (auto f : m.faces()) impl.face_normal[static_cast<std::size_t>(f)] = vec(CGAL::ORIGIN + PMP::compute_face_normal(f, m));
  impl.lo = impl.hi = vec(m.point(*m.vertices().begin()));
  for (auto v : m.vertices()) {
    impl.lo = impl.lo.cwiseMin(vec(m.point(v)));
    impl.hi = impl.hi.cwiseMax(vec(m.point(v)));
  }
  impl.tree.emplace(m.faces().begin(), m.faces().end(), m);
  impl.tree->build();
  impl.tree->accelerate_distance_queries();
  impl.side.emplace(*impl.tree);
}
}  // namespace

ClosedSurface read_closed_surface(const std::string& path) {
  PolygonSoup soup = read_polygon_soup(path);
  for (std::size_t k = 0; k < soup.points.size(); ++k)
    check<InputError>(soup.points[k].cwiseAbs().maxCoeff() <= max_coordinate, path, ": vertex ", k, " is beyond +-",
                      max_coordinate, " (rescale the geometry)");
  ClosedSurface s;
  auto& impl = *s.impl_;
  to_surface_frame(soup, impl);
  std::vector<K::Point_3> points;
  points.reserve(soup.points.size());
  for (const Vec3& x : soup.points) points.push_back(point(x));
  dirichlet_regions(soup, points, impl);
  repair_and_orient(path, points, soup.faces);
  PMP::polygon_soup_to_polygon_mesh(points, soup.faces, impl.mesh);
  check_closed_mesh(path, impl.mesh);
  finish_surface(path, impl);
  return s;
}

namespace {
// The boundary particles of a fill: sharp edges and corners first, then a Poisson-disk set
// on the faces; tagged by the surface's Neumann regions.
void add_surface_particles(const ClosedSurface& surface, const GeometryFill& f, PointCloud& cloud) {
  const auto& impl = surface.impl();
  const Mesh& m = impl.mesh;
  const Real area_density = 30 * impl.area / (f.spacing * f.spacing);
  // Sharp edges (faces meeting at more than 40 degrees) and their vertices get particles of
  // their own first, so that edges and corners are resolved and carry a normal between the
  // faces'; a vertex's normal is its faces' normals weighted by their angles at the vertex
  // (independent of how the faces are triangulated).
  const Real sharp_cos = std::cos(40.0 * 3.141592653589793 / 180);
  std::vector<Vec3> vertex_normal(m.number_of_vertices(), Vec3::Zero());
  for (auto h : m.halfedges())
    if (!m.is_border(h))
      vertex_normal[static_cast<std::size_t>(m.target(h))] += corner_angle(m, h) * impl.face_normal[static_cast<std::size_t>(m.face(h))];
  for (auto& n : vertex_normal) n.normalize();
  std::vector<char> corner(m.number_of_vertices(), 0);
  std::vector<Vec3> edge_pts, edge_nrm;
  for (auto e : m.edges()) {
    const auto h = m.halfedge(e);
    const Vec3 &n1 = impl.face_normal[static_cast<std::size_t>(m.face(h))],
               &n2 = impl.face_normal[static_cast<std::size_t>(m.face(m.opposite(h)))];
    if (n1.dot(n2) >= sharp_cos) continue;
    corner[static_cast<std::size_t>(m.source(h))] = corner[static_cast<std::size_t>(m.target(h))] = 1;
    const Vec3 a = vec(m.point(m.source(h))), b = vec(m.point(m.target(h)));
    const Vec3 n = (n1 + n2).normalized();
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.1 * f.spacing))));
    for (int k = 1; k < pieces; ++k) {  // dense candidates, thinned below
      edge_pts.push_back(a + (b - a) * (static_cast<Real>(k) / pieces));
      edge_nrm.push_back(n);
    }
  }
  std::vector<Vec3> corner_pts, corner_nrm;
  for (auto v : m.vertices())
    if (corner[static_cast<std::size_t>(v)]) {
      corner_pts.push_back(vec(m.point(v)));
      corner_nrm.push_back(vertex_normal[static_cast<std::size_t>(v)]);
    }
  // Sharp-edge vertices closer than half a spacing (a finely triangulated crease) are thinned too.
  std::vector<Vec3> fixed, fixed_nrm;
  for (std::size_t k : thin_to_blue_noise(corner_pts, 0.5 * f.spacing, {}, f.seed)) {
    fixed.push_back(corner_pts[k]);
    fixed_nrm.push_back(corner_nrm[k]);
  }
  for (std::size_t k : thin_to_blue_noise(edge_pts, blue_noise_radius_factor(1) * f.spacing, fixed, f.seed + 1)) {
    fixed.push_back(edge_pts[k]);
    fixed_nrm.push_back(edge_nrm[k]);
  }
  // The faces: about 30 random candidates per spacing^2, thinned to a Poisson-disk set.
  std::vector<Real> cumulative;
  std::vector<Mesh::Face_index> face_of;
  Real total = 0;
  for (auto fc : m.faces()) {
    total += PMP::face_area(fc, m);
    cumulative.push_back(total);
    face_of.push_back(fc);
  }
  const auto candidates = static_cast<std::uint64_t>(std::ceil(area_density));
  std::vector<Vec3> cand, cand_nrm;
  cand.reserve(candidates);
  cand_nrm.reserve(candidates);
  for (std::uint64_t k = 0; k < candidates; ++k) {
    const Real u = detail::uniform01(f.seed, k, 0) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
    const auto fc = face_of[static_cast<std::size_t>(std::min<std::ptrdiff_t>(it - cumulative.begin(), static_cast<std::ptrdiff_t>(face_of.size()) - 1))];
    const auto c = corners(m, fc);
    const Real s = std::sqrt(detail::uniform01(f.seed, k, 1)), t = detail::uniform01(f.seed, k, 2);
    cand.push_back((1 - s) * c[0] + s * (1 - t) * c[1] + s * t * c[2]);  // uniform on the triangle
    cand_nrm.push_back(impl.face_normal[static_cast<std::size_t>(fc)]);
  }
  const auto put = [&cloud](const Vec3& x, Tag t, const Vec3& n) {
    cloud.positions.push_back(x);
    cloud.tags.push_back(t);
    cloud.normals.push_back(n);
  };
  const auto kind = [&impl](const Vec3& x) { return on_neumann_region_in_frame(impl, x) ? Tag::Neumann : Tag::Dirichlet; };
  for (std::size_t k = 0; k < fixed.size(); ++k) put(fixed[k], kind(fixed[k]), fixed_nrm[k]);
  for (std::size_t k : thin_to_blue_noise(cand, blue_noise_radius_factor(2) * f.spacing, fixed, f.seed + 2))
    put(cand[k], kind(cand[k]), cand_nrm[k]);
}
}  // namespace

PointCloud fill_surface(const ClosedSurface& surface, const GeometryFill& fill) {
  check<ConfigError>(std::isfinite(fill.spacing) && fill.spacing > 0, "the spacing must be positive and finite, got ",
                     fill.spacing);
  check<ConfigError>(std::isfinite(fill.delta) && fill.delta >= 0 && fill.delta < 0.5,
                     "the perturbation must be in [0, 0.5), got ", fill.delta);
  // The whole fill runs in the surface's own frame (see ClosedSurface::Impl); the particles
  // are mapped back to the file's coordinates at the end.
  const auto& impl = surface.impl();
  GeometryFill f = fill;
  f.spacing = fill.spacing / impl.unit;
  const Vec3 lo = impl.lo, hi = impl.hi;
  const Real smallest = (hi - lo).minCoeff();
  check<ConfigError>(f.spacing * 3 <= smallest, "the spacing ", fill.spacing, " is too large for the geometry: its ",
                     "bounding box is ", smallest * impl.unit, " thin (at least 3 particles across are needed)");
  const double lattice = ((hi[0] - lo[0]) / f.spacing + 1) * ((hi[1] - lo[1]) / f.spacing + 1) * ((hi[2] - lo[2]) / f.spacing + 1);
  const double on_surface = 30 * impl.area / (f.spacing * f.spacing);
  detail::check_lattice_size(std::max(lattice, on_surface), fill.spacing);
  check_memory_estimate(lattice / f.parts * (2 * sizeof(Vec3) + sizeof(Tag)) + (f.part == 0 ? on_surface * 2 * sizeof(Vec3) : 0),
                        detail::concat("the cloud of the geometry (up to ", lattice, " particles)"), "choose a larger --spacing");

  PointCloud cloud;
  cloud.dim = 3;
  cloud.spacing = f.spacing;
  if (f.part == 0) add_surface_particles(surface, f, cloud);  // (a part > 0: interior layers only)
  // Interior: at least half a spacing inside the surface.
  const auto admissible = [&](const Vec3& x) {
    return contains_in_frame(impl, x) && distance_in_frame(impl, x) >= 0.5 * f.spacing;
  };
  detail::add_interior_particles(cloud, lo, hi, f, f.seed + 3, admissible);
  // A plate or needle thinner than about one spacing leaves no particle half a spacing inside.
  check<ConfigError>(f.parts > 1 || cloud.count(Tag::Interior) > 0, "the geometry leaves no room for interior particles ",
                     "at the spacing ", fill.spacing, " (it is thinner than about one spacing); choose a smaller --spacing");
  for (Vec3& x : cloud.positions) x = impl.from_frame(x);
  cloud.spacing = fill.spacing;
  if (cloud.size() > 0 || f.parts == 1) validate(cloud);  // (a part may be empty)
  return cloud;
}

}  // namespace vrsph
