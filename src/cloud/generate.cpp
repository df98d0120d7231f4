// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include "random.hpp"

namespace vrsph {

namespace {

// Position, normal and tag of one particle.
constexpr double bytes_per_particle = 2 * sizeof(Vec3) + sizeof(Tag);

void check_box(const Domain& box, int n) {
  check<InputError>(box.shape == Domain::Shape::Box, "lattice generators need a box domain");
  check<ConfigError>(n >= 1, "number of intervals per direction must be >= 1, got ", n);
  check<ConfigError>(n <= 100000, "number of intervals per direction ", n, " is unreasonably large");
}

// Tensor product of per-axis coordinate lists; tag by position relative to the box.
PointCloud tensor_cloud(const Domain& box, const std::vector<std::vector<Real>>& axes, Real spacing,
                        const ParticleRange& range) {
  PointCloud c;
  c.dim = box.dim;
  c.domain = box;
  c.spacing = spacing;
  c.normals.reserve(1);
  c.normals.clear();
  double whole = 1;
  for (int k = 0; k < box.dim; ++k) whole *= static_cast<double>(axes[static_cast<std::size_t>(k)].size());
  check<ConfigError>(range.end < 0 || (0 <= range.begin && range.begin <= range.end && range.end <= whole),
                     "particle range ", range.begin, "..", range.end, " of a lattice of ", whole, " particles");
  const double total_estimate = range.end < 0 ? whole : range.end - range.begin;
  check_memory_estimate(total_estimate * bytes_per_particle, detail::concat("the point cloud (", total_estimate, " particles)"),
                        "reduce --n (intervals per direction) or the dimension");
  const std::size_t nx = axes[0].size(), ny = box.dim > 1 ? axes[1].size() : 1, nz = box.dim > 2 ? axes[2].size() : 1;
  const std::size_t first = range.end < 0 ? 0 : static_cast<std::size_t>(range.begin);
  const std::size_t total = range.end < 0 ? nx * ny * nz : static_cast<std::size_t>(range.end - range.begin);
  c.positions.resize(total);
  c.tags.resize(total);
  c.normals.resize(total);
  const Real tol = 1e-12 * spacing;
  // x fastest, then y, then z: particle (kx, ky, kz) is number kx + nx (ky + ny kz).
#pragma omp parallel for schedule(static) if (total > 4096)
  for (std::size_t local = 0; local < total; ++local) {
    const std::size_t flat = first + local;
    const std::size_t kx = flat % nx, ky = flat / nx % ny, kz = flat / (nx * ny);
    Vec3 x = Vec3::Zero();
    x[0] = axes[0][kx];
    if (box.dim > 1) x[1] = axes[1][ky];
    if (box.dim > 2) x[2] = axes[2][kz];
    const Real sd = box.signed_distance(x);
    Tag tag = Tag::Interior;
    Vec3 normal = Vec3::Zero();
    if (sd < -tol) {
      tag = Tag::Ghost;
    } else if (sd <= tol) {
      tag = Tag::Dirichlet;
      normal = box.outward_normal(x, tol);
    }
    c.positions[local] = x;
    c.tags[local] = tag;
    c.normals[local] = normal;
  }
  return c;
}

Real box_spacing(const Domain& box, int n) {
  Real prod = 1;
  for (int k = 0; k < box.dim; ++k) prod *= (box.hi[k] - box.lo[k]) / n;
  return std::pow(prod, 1.0 / box.dim);
}

}  // namespace

int ghost_layers_for(Real support_radius, Real dx) {
  check<InputError>(dx > 0 && support_radius > 0, "ghost layers need positive h and dx");
  const Real layers = std::ceil((support_radius + dx) / dx - 1e-9);
  check<ConfigError>(layers <= 100000, "a ghost layer of ", layers, " particle layers (support radius ", support_radius,
                     ", spacing ", dx, ") is unreasonable: reduce the smoothing radius");
  return static_cast<int>(layers);
}

PointCloud vertex_lattice(const Domain& box, int n, int ghost_layers, const ParticleRange& range) {
  check_box(box, n);
  check<ConfigError>(ghost_layers >= 0, "ghost layers must be >= 0");
  std::vector<std::vector<Real>> axes(3);
  for (int k = 0; k < box.dim; ++k) {
    const Real dx = (box.hi[k] - box.lo[k]) / n;
    if (box.periodic[static_cast<std::size_t>(k)]) {  // lo is hi's image: n points, no ghosts
      for (int i = 0; i < n; ++i) axes[static_cast<std::size_t>(k)].push_back(box.lo[k] + i * dx);
      continue;
    }
    for (int i = -ghost_layers; i <= n + ghost_layers; ++i)
      axes[static_cast<std::size_t>(k)].push_back(i == n ? box.hi[k] : box.lo[k] + i * dx);
  }
  return tensor_cloud(box, axes, box_spacing(box, n), range);
}

PointCloud cell_centred_lattice(const Domain& box, int n, bool boundary_particles, int ghost_layers,
                                const ParticleRange& range) {
  check_box(box, n);
  check<ConfigError>(ghost_layers >= 0, "ghost layers must be >= 0");
  std::vector<std::vector<Real>> axes(3);
  for (int k = 0; k < box.dim; ++k) {
    const Real dx = (box.hi[k] - box.lo[k]) / n;
    auto& a = axes[static_cast<std::size_t>(k)];
    if (box.periodic[static_cast<std::size_t>(k)]) {  // n cell centres, no boundary particles or ghosts
      for (int i = 0; i < n; ++i) a.push_back(box.lo[k] + (i + 0.5) * dx);
      continue;
    }
    for (int i = -ghost_layers; i < n + ghost_layers; ++i) {
      if (boundary_particles && i == 0) a.push_back(box.lo[k]);
      if (boundary_particles && i == n) a.push_back(box.hi[k]);
      a.push_back(box.lo[k] + (i + 0.5) * dx);
    }
    if (boundary_particles && ghost_layers == 0) a.push_back(box.hi[k]);
  }
  return tensor_cloud(box, axes, box_spacing(box, n), range);
}

void perturb(PointCloud& cloud, const PerturbOptions& o) {
  validate(cloud);
  check<ConfigError>(std::isfinite(o.delta) && o.delta >= 0 && o.delta < 1,
                    "perturbation amplitude delta must be in [0, 1), got ", o.delta);
  check<InputError>(cloud.spacing > 0, "perturbation needs the cloud spacing dx");
  check<ConfigError>(std::isfinite(o.regular_layer) && o.regular_layer >= 0, "regular layer width must be >= 0, got ",
                    o.regular_layer);
  const bool bounded = o.bounded >= 0 ? o.bounded == 1 : cloud.count(Tag::Dirichlet) + cloud.count(Tag::Neumann) > 0;
  const Real amp = o.delta * cloud.spacing;
  // Each particle's step depends only on (seed, particle, axis): threads change nothing.
#pragma omp parallel for schedule(static) if (cloud.size() > 4096)
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Tag tag = cloud.tags[si];
    Vec3 step = Vec3::Zero();
    for (int k = 0; k < cloud.dim; ++k)
      step[k] = amp * (2 * detail::uniform01(o.seed, static_cast<std::uint64_t>(i) + static_cast<std::uint64_t>(o.first_index),
                                             static_cast<std::uint64_t>(k)) - 1);
    if (tag == Tag::Dirichlet || tag == Tag::Neumann) {
      if (!o.boundary_tangential || !cloud.has_normals()) continue;
      // Move only along the face: drop the normal component; skip edges/corners
      // (normal not aligned with an axis) and curved boundaries.
      const Vec3& nrm = cloud.normals[si];
      if (cloud.domain.shape != Domain::Shape::Box || std::abs(nrm.cwiseAbs().maxCoeff() - 1) > 1e-12) continue;
      step -= step.dot(nrm) * nrm;
      const Vec3 x = cloud.positions[si] + step;
      bool inside_face = true;  // stay strictly inside the face, off its edges
      for (int k = 0; k < cloud.dim; ++k)
        if (std::abs(nrm[k]) < 0.5 && !cloud.domain.periodic[static_cast<std::size_t>(k)])
          inside_face = inside_face && x[k] > cloud.domain.lo[k] && x[k] < cloud.domain.hi[k];
      if (inside_face) cloud.positions[si] = cloud.domain.wrap(x);
      continue;
    }
    if (o.regular_layer > 0 && tag == Tag::Interior && cloud.domain.shape == Domain::Shape::Box) {
      const Vec3& x0 = cloud.positions[si];
      for (int k = 0; k < cloud.dim; ++k)
        if (!cloud.domain.periodic[static_cast<std::size_t>(k)] &&
            std::min(x0[k] - cloud.domain.lo[k], cloud.domain.hi[k] - x0[k]) < o.regular_layer * cloud.spacing)
          step[k] = 0;
    }
    Vec3 x = cloud.positions[si] + step;
    if (bounded && tag == Tag::Interior) {
      for (int halvings = 0; halvings < 30 && cloud.domain.signed_distance(x) < 0.1 * cloud.spacing; ++halvings) {
        step *= 0.5;
        x = cloud.positions[si] + step;
      }
    }
    cloud.positions[si] = cloud.domain.wrap(x);  // across a periodic face: back into the box
  }
  if (!bounded && cloud.domain.shape != Domain::Shape::None) {
#pragma omp parallel for schedule(static) if (cloud.size() > 4096)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      cloud.tags[si] = cloud.domain.signed_distance(cloud.positions[si]) >= 0 ? Tag::Interior : Tag::Ghost;
    }
  }
}

namespace {
// The ball cloud's numbering without its particles: interior lattice points row by row
// (x outermost, the last axis innermost), then the surface particles. A row's points are
// those of the inner index t with |t| <= T (the distance to the centre grows with |t|, and
// +t and -t give the same square), so its count comes from a bisection for T.
struct BallLayout {
  int dim = 1, m = 0;
  Real radius = 0, dx = 0;
  Domain ball;
  std::vector<Index> row_start;  ///< first interior number of each row, and the total last
  Index surface = 0;             ///< surface particles (after the interior ones)

  BallLayout(int d, Real r, int n) : dim(d), m(n / 2 + 1), radius(r), dx(2 * r / n), ball(Domain::ball(d, Vec3::Zero(), r)) {
    const int rows_per_axis = 2 * m + 1, rows = dim == 1 ? 1 : dim == 2 ? rows_per_axis : rows_per_axis * rows_per_axis;
    row_start.assign(static_cast<std::size_t>(rows) + 1, 0);
    for (int row = 0; row < rows; ++row) {
      const int reach = half_width(row);
      row_start[static_cast<std::size_t>(row) + 1] = row_start[static_cast<std::size_t>(row)] + (reach < 0 ? 0 : 2 * reach + 1);
    }
    if (dim == 1) surface = 2;
    else if (dim == 2) surface = std::max(8, static_cast<int>(std::lround(2 * std::numbers::pi * radius / dx)));
    else surface = std::max(12, static_cast<int>(std::lround(4 * std::numbers::pi * radius * radius / (dx * dx))));
  }
  Index interior() const { return row_start.back(); }
  Index size() const { return interior() + surface; }
  // Lattice point t of a row: rows are (k) in 2D and (k, j) in 3D, k outermost.
  Vec3 point(int row, int t) const {
    if (dim == 1) return Vec3(t * dx, 0, 0);
    if (dim == 2) return Vec3((row - m) * dx, t * dx, 0);
    return Vec3((row / (2 * m + 1) - m) * dx, (row % (2 * m + 1) - m) * dx, t * dx);
  }
  // At least dx/2 inside the surface (the test every interior point passes).
  bool inside(const Vec3& x) const { return ball.signed_distance(x) >= 0.5 * dx - 1e-12 * dx; }
  // The largest t in [0, m] of a row whose point is inside, -1 if none.
  int half_width(int row) const {
    if (!inside(point(row, 0))) return -1;
    int lo = 0, hi = m;  // inside(lo) holds
    while (lo < hi) {
      const int mid = lo + (hi - lo + 1) / 2;
      if (inside(point(row, mid))) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }
  // Surface particle s: its outward normal (the position is radius x normal).
  Vec3 surface_normal(Index s) const {
    if (dim == 1) return Vec3(s == 0 ? -1 : 1, 0, 0);
    if (dim == 2) {
      const Real t = 2 * std::numbers::pi * static_cast<Real>(s) / static_cast<Real>(surface);
      return Vec3(std::cos(t), std::sin(t), 0);
    }
    const Real golden = std::numbers::pi * (3 - std::sqrt(5.0));
    const Real z = 1 - 2 * (static_cast<Real>(s) + 0.5) / static_cast<Real>(surface), rr = std::sqrt(1 - z * z),
               t = golden * static_cast<Real>(s);
    return Vec3(rr * std::cos(t), rr * std::sin(t), z);
  }
};

void check_ball(int dim, Real radius, int n) {
  check<InputError>(dim >= 1 && dim <= 3, "ball cloud dimension must be 1, 2 or 3, got ", dim);
  check<InputError>(radius > 0 && std::isfinite(radius), "ball radius must be positive, got ", radius);
  check<ConfigError>(n >= 2 && n <= 100000, "ball cloud needs n in 2..100000 intervals per diameter, got ", n);
  check<ConfigError>(dim < 3 || n <= 4000, "a 3D ball cloud with n = ", n, " intervals per diameter is unreasonably large");
}
}  // namespace

Index ball_cloud_size(int dim, Real radius, int n) {
  check_ball(dim, radius, n);
  return BallLayout(dim, radius, n).size();
}

PointCloud ball_cloud(int dim, Real radius, int n, const ParticleRange& range) {
  check_ball(dim, radius, n);
  const BallLayout layout(dim, radius, n);
  const Index whole = layout.size();
  check<ConfigError>(range.end < 0 || (0 <= range.begin && range.begin <= range.end && range.end <= whole),
                     "particle range ", range.begin, "..", range.end, " of a ball cloud of ", whole, " particles");
  const Index begin = range.end < 0 ? 0 : range.begin, end = range.end < 0 ? whole : range.end;
  PointCloud c;
  c.dim = dim;
  c.domain = Domain::ball(dim, Vec3::Zero(), radius);
  c.spacing = layout.dx;
  check_memory_estimate(static_cast<double>(end - begin) * bytes_per_particle,
                        detail::concat("the ball cloud (", end - begin, " particles)"),
                        "reduce --n (intervals per diameter) or the dimension");
  c.positions.reserve(static_cast<std::size_t>(end - begin));
  c.tags.reserve(static_cast<std::size_t>(end - begin));
  c.normals.reserve(static_cast<std::size_t>(end - begin));
  // Interior rows that overlap [begin, end), each from its first number.
  const auto first_row = std::upper_bound(layout.row_start.begin(), layout.row_start.end(), begin) - layout.row_start.begin() - 1;
  for (auto row = static_cast<std::size_t>(std::max<std::ptrdiff_t>(first_row, 0));
       row + 1 < layout.row_start.size() && layout.row_start[row] < end; ++row) {
    const Index count = layout.row_start[row + 1] - layout.row_start[row], reach = (count - 1) / 2;
    for (Index t = 0; t < count; ++t) {
      const Index number = layout.row_start[row] + t;
      if (number < begin || number >= end) continue;
      c.positions.push_back(layout.point(static_cast<int>(row), static_cast<int>(t - reach)));
      c.tags.push_back(Tag::Interior);
      c.normals.push_back(Vec3::Zero());
    }
  }
  for (Index s = std::max<Index>(begin - layout.interior(), 0); s < layout.surface && layout.interior() + s < end; ++s) {
    const Vec3 nrm = layout.surface_normal(s);
    c.positions.push_back(radius * nrm);
    c.tags.push_back(Tag::Dirichlet);
    c.normals.push_back(nrm);
  }
  return c;
}

}  // namespace vrsph
