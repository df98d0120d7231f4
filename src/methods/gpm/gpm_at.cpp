// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include <vrsph/methods/gpm/gpm_at.hpp>
#include <vrsph/methods/gpm/gpm_pairs.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

GpmPointValues gpm_at_points(const PointCloud& cloud, std::span<const Real> volumes, const std::string& family, Real h,
                             const std::vector<Vec3>& points, std::span<const Real> u, std::span<const Real> u_at_points) {
  const auto n = static_cast<std::size_t>(cloud.size());
  check<InputError>(volumes.size() == n && u.size() == n, "gpm at points: ", volumes.size(), " volumes and ", u.size(),
                    " values for ", n, " particles");
  check<InputError>(u_at_points.size() == points.size(), "gpm at points: ", u_at_points.size(), " values for ",
                    points.size(), " points");
  check<ConfigError>(family == "1" || family == "2" || family == "3", "gpm weight must be 1, 2 or 3, got '", family, "'");
  const int d = cloud.dim;
  for (std::size_t q = 0; q < points.size(); ++q)
    for (int k = d; k < 3; ++k)
      check<InputError>(points[q][k] == 0, "evaluation point ", q, " has a non-zero coordinate ", "xyz"[k], " = ",
                        points[q][k], " in a ", d, "D cloud");
  const ReferenceWeight wv = reference_weight("pi" + family, d), wg = reference_weight("grad" + family, d),
                        wl = reference_weight("delta" + family, d);
  const auto near = particles_within(cloud, points, h);
  GpmPointValues out;
  const auto m = static_cast<Eigen::Index>(points.size());
  out.value = Eigen::VectorXd::Zero(m);
  out.laplacian = Eigen::VectorXd::Zero(m);
  out.gradient = Eigen::MatrixXd::Zero(m, d);
  out.neighbours.resize(points.size());
  for (std::size_t q = 0; q < points.size(); ++q) {
    const Vec3& x = points[q];
    check<GeometryError>(!near[q].empty(), "evaluation point ", q, " at (", x[0], ", ", x[1], ", ", x[2],
                         ") has no particle closer than h = ", h, " (h is below the covering radius there)");
    out.neighbours[q] = static_cast<Index>(near[q].size());
    const auto e = static_cast<Eigen::Index>(q);
    for (Index j : near[q]) {
      const auto sj = static_cast<std::size_t>(j);
      const Vec3 xji = cloud.positions[sj] - x;
      const Real r = xji.norm();
      out.value[e] += gpm::value_weight(volumes[sj], wv.value(r, h)) * u[sj];
      if (r == 0) continue;  // Lambda(x) leaves out a particle at x itself
      const Real du = u[sj] - u_at_points[q];
      const Vec3 g = gpm::gradient_weight(d, volumes[sj], wg.value(r, h), r, xji) * du;
      for (int k = 0; k < d; ++k) out.gradient(e, k) += g[k];
      out.laplacian[e] += gpm::laplacian_weight(d, volumes[sj], wl.value(r, h), r) * du;
    }
  }
  return out;
}

}  // namespace vrsph
