// SPDX-License-Identifier: BSD-3-Clause
// Particle shifting (shifting.hpp).
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/shifting.hpp>

namespace vrsph {

Shifting parse_shifting(const std::string& name) {
  if (name == "none") return Shifting::None;
  if (name == "xu") return Shifting::Xu;
  if (name == "lind") return Shifting::Lind;
  throw ConfigError(detail::concat("unknown shifting '", name, "' (known: none, xu, lind)"));
}

std::string to_string(Shifting s) { return s == Shifting::None ? "none" : s == Shifting::Xu ? "xu" : "lind"; }

std::vector<Vec3> shifting_displacements(const Discretisation& disc, const ShiftingOptions& options,
                                         const Eigen::MatrixXd& u, Real dt) {
  check<ConfigError>(std::isfinite(options.coefficient) && options.coefficient >= 0,
                     "shifting: the coefficient must be finite and >= 0, got ", options.coefficient);
  check<ConfigError>(std::isfinite(options.max_shift) && options.max_shift >= 0,
                     "shifting: the largest shift must be finite and >= 0 spacings (0: unbounded), got ", options.max_shift);
  const PointCloud& cloud = disc.cloud;
  const NeighbourList& nl = disc.neighbours;
  const int d = cloud.dim;
  std::vector<Vec3> dr(static_cast<std::size_t>(cloud.size()), Vec3::Zero());
  if (options.kind == Shifting::None) return dr;
  const Real umax = u.rows() ? u.rowwise().norm().maxCoeff() : 0.0;
  const Real beta = options.coefficient > 0 ? options.coefficient : (options.kind == Shifting::Xu ? 0.04 : 2.0);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
    const Index count = nl.count(i);
    if (count == 0) continue;
    Vec3 sum = Vec3::Zero();
    Real mean_r = 0;
    const Kernel kernel = disc.kernel_at(i);
    for (Index k = 0; k < count; ++k) {
      const Vec3 xij = xi - disc.neighbour_position(i, k);
      const Real r = xij.norm();
      if (r <= 0) continue;
      mean_r += r;
      if (options.kind == Shifting::Xu)
        sum += xij / (r * r * r);
      else
        sum += kernel.dW_over_r(r) * xij;  // ∇_i W_ij = W'(r) x_ij / r
    }
    Vec3& out = dr[static_cast<std::size_t>(i)];
    if (options.kind == Shifting::Xu) {
      mean_r /= static_cast<Real>(count);
      out = beta * mean_r * mean_r * umax * dt * sum;
    } else {
      const Real ell = kernel.support() / kernel_info(kernel.type()).support_per_smoothing_length;
      const Real volume = std::pow(disc.spacing, d);
      out = -beta * ell * u.row(i).norm() * dt * volume * sum;
    }
    const Real limit = options.max_shift * disc.spacing;
    if (limit > 0 && out.norm() > limit) out *= limit / out.norm();
  }
  return dr;
}

}  // namespace vrsph
