// SPDX-License-Identifier: BSD-3-Clause
// Free-surface detection (free_surface.hpp).
#include <cmath>
#include <utility>
#include <Eigen/Eigenvalues>
#include <vrsph/analysis/free_surface.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

std::string_view surface_criterion_name(SurfaceCriterion c) {
  return c == SurfaceCriterion::Eigenvalue ? "eigenvalue" : "number-density";
}

SurfaceCriterion parse_surface_criterion(std::string_view name) {
  if (name == "eigenvalue") return SurfaceCriterion::Eigenvalue;
  if (name == "number-density") return SurfaceCriterion::NumberDensity;
  throw ConfigError(detail::concat("unknown free-surface criterion '", name, "' (known: eigenvalue, number-density)"));
}

namespace {

// The kernel sums of an interior particle of the lattice dx Z^d: the number density
// n_0 = sum_k W(|k| dx) (self included) and lambda_0 = sum_k V (-W'/r) (k_x dx)^2, the
// eigenvalue (every eigenvalue, by the lattice's symmetry) of the full support's M.
struct LatticeSums {
  Real density = 0, eigenvalue = 0;
};
LatticeSums lattice_sums(const Kernel& kernel, Real dx) {
  const int d = kernel.dim();
  const int reach = static_cast<int>(std::ceil(kernel.support() / dx));
  const Real volume = std::pow(dx, d);
  LatticeSums s;
  const int ky_reach = d >= 2 ? reach : 0, kz_reach = d >= 3 ? reach : 0;
  for (int kx = -reach; kx <= reach; ++kx)
    for (int ky = -ky_reach; ky <= ky_reach; ++ky)
      for (int kz = -kz_reach; kz <= kz_reach; ++kz) {
        const Real r = dx * std::sqrt(static_cast<Real>(kx * kx + ky * ky + kz * kz));
        if (r >= kernel.support()) continue;
        s.density += kernel.W(r);
        if (r > 0) s.eigenvalue += volume * -kernel.dW_over_r(r) * (kx * dx) * (kx * dx);
      }
  return s;
}

void check_options(const FreeSurfaceOptions& o) {
  auto in_unit = [](Real t) { return std::isfinite(t) && t > 0 && t < 1; };
  // More than 10 spacings is not a local test (and every particle would see thousands).
  check<ConfigError>(std::isfinite(o.h_factor) && o.h_factor > 0 && o.h_factor <= 10,
                     "free surface: the h-factor must be in (0, 10], got ", o.h_factor);
  check<ConfigError>(std::isfinite(o.spacing) && o.spacing >= 0, "free surface: the spacing must be >= 0 (0 = estimate), got ",
                     o.spacing);
  check<ConfigError>(in_unit(o.density_threshold), "free surface: the number-density threshold must lie in (0, 1), got ",
                     o.density_threshold);
  check<ConfigError>(in_unit(o.surface_eigenvalue) && in_unit(o.interior_eigenvalue),
                     "free surface: the eigenvalue thresholds must lie in (0, 1), got ", o.surface_eigenvalue, " and ",
                     o.interior_eigenvalue);
  check<ConfigError>(std::isfinite(o.film_eigenvalue) && o.film_eigenvalue >= 0 && o.film_eigenvalue < 1,
                     "free surface: the film eigenvalue threshold must lie in [0, 1) (0: off), got ", o.film_eigenvalue);
  check<ConfigError>(o.surface_eigenvalue <= o.interior_eigenvalue, "free surface: the surface eigenvalue threshold (",
                     o.surface_eigenvalue, ") exceeds the interior one (", o.interior_eigenvalue, ")");
}

// Smallest eigenvalue of the symmetric d x d block of M.
Real smallest_eigenvalue(const Eigen::Matrix3d& m, int d) {
  if (d == 1) return m(0, 0);
  if (d == 2) return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(m.topLeftCorner<2, 2>(), Eigen::EigenvaluesOnly)
      .eigenvalues()[0];
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m, Eigen::EigenvaluesOnly).eigenvalues()[0];
}

// The smallest eigenvalue of the symmetric d x d block of M and its unit eigenvector.
std::pair<Real, Vec3> smallest_eigenpair(const Eigen::Matrix3d& m, int d) {
  Vec3 v = Vec3::Zero();
  if (d == 1) {
    v[0] = 1;
    return {m(0, 0), v};
  }
  if (d == 2) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(m.topLeftCorner<2, 2>());
    v.head<2>() = es.eigenvectors().col(0);
    return {es.eigenvalues()[0], v};
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  return {es.eigenvalues()[0], es.eigenvectors().col(0)};
}

// -M^{-1} g normalised (g = sum_j V grad_i W_ij), or -g where M is (nearly) singular; 0 if
// the direction is undefined.
Vec3 outward_normal(const Eigen::Matrix3d& m, const Vec3& g, int d, Real lambda_min, Real lambda_0, Real dx) {
  Vec3 n = Vec3::Zero();
  if (lambda_min > 1e-6 * lambda_0) {
    if (d == 1) n[0] = g[0] / m(0, 0);
    else if (d == 2) n.head<2>() = m.topLeftCorner<2, 2>().ldlt().solve(g.head<2>());
    else n = m.ldlt().solve(g);
  } else {
    n = g;
  }
  n = -n;
  const Real len = n.norm();  // unused coordinates are 0
  // g ~ 1/dx where the support is cut; a full, symmetric support has g = 0 up to round-off.
  if (!(len > 1e-8 / dx)) return Vec3::Zero();
  return n / len;
}

}  // namespace

FreeSurface detect_free_surface(const PointCloud& cloud, const FreeSurfaceOptions& options) {
  check_options(options);
  validate(cloud);
  const int d = cloud.dim;
  const Index n = cloud.size();
  FreeSurface out;
  out.spacing = options.spacing > 0 ? options.spacing : estimate_spacing(cloud);
  out.radius = options.h_factor * out.spacing;
  const Kernel kernel(options.kernel, d, out.radius);
  const LatticeSums full = lattice_sums(kernel, out.spacing);
  const Real volume = std::pow(out.spacing, d);

  SearchParams sp;
  sp.radius = out.radius;
  sp.min_neighbours = 0;  // a lone droplet particle is a surface particle, not an error
  const NeighbourList nl = find_neighbours(cloud, sp);
  const bool periodic = !nl.shifts.empty();

  out.surface.assign(static_cast<std::size_t>(n), 0);
  out.normals.assign(static_cast<std::size_t>(n), Vec3::Zero());
  out.density_ratio.assign(static_cast<std::size_t>(n), 0);
  out.eigenvalue.assign(static_cast<std::size_t>(n), 0);
  out.scanned.assign(static_cast<std::size_t>(n), 0);
  // Films (FreeSurfaceOptions::film_eigenvalue): the direction across a fluid particle's fluid
  // neighbours where they alone are thin and the support is open (0 elsewhere).
  const bool films = options.criterion == SurfaceCriterion::Eigenvalue && options.only_interior && options.film_eigenvalue > 0;
  std::vector<Vec3> across_film(films ? static_cast<std::size_t>(n) : 0, Vec3::Zero());
  const Real s = out.radius / 2;  // the scan's length: its region reaches the support radius

  auto pair = [&](Index i, Index k) -> Vec3 {  // x_j - x_i (its periodic image)
    Vec3 v = cloud.positions[static_cast<std::size_t>(nl.indices[static_cast<std::size_t>(k)])] -
             cloud.positions[static_cast<std::size_t>(i)];
    if (periodic) v += periodic_shift(cloud.domain, nl.shifts[static_cast<std::size_t>(k)]);
    return v;
  };
  // Two passes: the scan reads the neighbours' eigenvalues.
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    Real density = kernel.W(0);
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero(), fluid = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero();
    for (Index k = nl.offsets[iu]; k < nl.offsets[iu + 1]; ++k) {
      const Vec3 xji = pair(i, k);
      const Real r = nl.distances[static_cast<std::size_t>(k)];
      density += kernel.W(r);
      const Real f = kernel.dW_over_r(r);  // W'(r)/r <= 0
      const Eigen::Matrix3d mk = (volume * -f) * (xji * xji.transpose());
      m += mk;
      if (films && cloud.tags[static_cast<std::size_t>(nl.indices[static_cast<std::size_t>(k)])] == Tag::Interior) fluid += mk;
      g += (volume * f) * (-xji);  // grad_i W_ij = W'(r) x_ij / r, x_ij = x_i - x_j
    }
    out.density_ratio[iu] = density / full.density;
    const Real lambda = smallest_eigenvalue(m, d);
    out.eigenvalue[iu] = lambda / full.eigenvalue;
    if (out.eigenvalue[iu] < options.interior_eigenvalue)
      out.normals[iu] = outward_normal(m, g, d, lambda, full.eigenvalue, out.spacing);
    // A film: the support open (a normal) and the fluid neighbours alone thin. Across them, to
    // the side the renormalised normal points to (the walls turn it away from themselves); that
    // normal itself may run along the film.
    const Vec3& nrm = out.normals[iu];
    if (films && cloud.tags[iu] == Tag::Interior && nrm.squaredNorm() > 0) {
      const auto [mu, across] = smallest_eigenpair(fluid, d);
      // (A particle with no fluid neighbour, a droplet beside a wall, keeps the renormalised
      // normal: every direction is "across" nothing.)
      if (mu < options.film_eigenvalue * full.eigenvalue)
        across_film[iu] = fluid.trace() == 0 ? nrm : nrm.dot(across) < 0 ? Vec3(-across) : across;
    }
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    if (options.only_interior && cloud.tags[iu] != Tag::Interior) continue;
    bool surface = false;
    if (options.criterion == SurfaceCriterion::NumberDensity) {
      surface = out.density_ratio[iu] < options.density_threshold;
    } else if (films && across_film[iu].squaredNorm() > 0) {
      surface = true;
      out.normals[iu] = across_film[iu];
    } else if (out.eigenvalue[iu] < options.surface_eigenvalue) {
      surface = true;
    } else if (out.eigenvalue[iu] <= options.interior_eigenvalue) {
      surface = true;
      const Vec3& nrm = out.normals[iu];
      if (options.scan && nrm.squaredNorm() > 0) {
        out.scanned[iu] = 1;
        const Vec3 centre = s * nrm;  // T - x_i
        for (Index k = nl.offsets[iu]; k < nl.offsets[iu + 1] && surface; ++k) {
          const auto ju = static_cast<std::size_t>(nl.indices[static_cast<std::size_t>(k)]);
          const bool wall = options.only_interior && cloud.tags[ju] != Tag::Interior;
          if (!wall && !options.scan_every_neighbour && out.eigenvalue[ju] < options.surface_eigenvalue) continue;
          const Vec3 xji = pair(i, k);
          const Real r = nl.distances[static_cast<std::size_t>(k)];
          const bool in_cone = r < std::sqrt(2.0) * s && xji.dot(nrm) > r * std::sqrt(0.5);
          // A wall covers the particle only inside the cone: the cap reaches down to a floor next
          // to a free face (the foot of a water column), which would hide the face.
          const bool in_cap = !wall && (xji - centre).norm() < s;
          if (in_cone || in_cap) surface = false;
        }
      }
    }
    out.surface[iu] = surface ? 1 : 0;
  }
  for (auto f : out.surface) out.count += f;
  return out;
}

}  // namespace vrsph
