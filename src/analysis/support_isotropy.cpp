// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vrsph/analysis/support_isotropy.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>

namespace vrsph {

namespace {
// λ_min / λ_max of the leading d x d block of a symmetric positive semi-definite m (fixed-size
// closed forms: a dynamic eigensolver allocated per particle).
Real eigenvalue_ratio(const Eigen::Matrix3d& m, int d) {
  Real lo = 0, hi = 0;
  if (d == 1) {
    lo = hi = m(0, 0);
  } else if (d == 2) {
    const Real mean = 0.5 * (m(0, 0) + m(1, 1));
    const Real rad = std::hypot(0.5 * (m(0, 0) - m(1, 1)), m(1, 0));
    lo = mean - rad;
    hi = mean + rad;
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(m, Eigen::EigenvaluesOnly);
    lo = es.eigenvalues()[0];
    hi = es.eigenvalues()[2];
  }
  return hi > 0 ? std::max(Real(0), lo) / hi : Real(0);
}
}  // namespace

Field support_isotropy(const PointCloud& cloud, const NeighbourList& nl) {
  const Index n = cloud.size();
  check<InputError>(nl.size() == n, "support isotropy: a neighbour list of ", nl.size(), " rows for ", n, " particles");
  check<InputError>(nl.distances.size() == static_cast<std::size_t>(nl.total()),
                    "support isotropy: the neighbour list has no distances");
  const bool periodic = !nl.shifts.empty();
  const int d = cloud.dim;
  Field ratio(n);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const auto nbr = nl.of(i);
    const auto dist = nl.distances_of(i);
    const Real h = nl.radius(i);
    const Vec3& xi = cloud.positions[si];
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Real r = dist[k];
      if (!(r < h) || r == 0) continue;
      Vec3 dx = cloud.positions[static_cast<std::size_t>(nbr[k])] - xi;
      if (periodic) dx += periodic_shift(cloud.domain, nl.shifts[static_cast<std::size_t>(nl.offsets[si]) + k]);
      const Real w = (1 - r / h) * (1 - r / h);
      m += w * dx * dx.transpose();
    }
    ratio[i] = eigenvalue_ratio(m, d);
  }
  return ratio;
}

}  // namespace vrsph
