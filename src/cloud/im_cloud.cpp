// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/cloud/im_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include "random.hpp"

namespace vrsph {

void im_lattice_range(Real dx, Real margin, long long& first, long long& last) {
  // Strict inequalities: a lattice point exactly on the boundary of Omega_H is left out.
  first = static_cast<long long>(std::floor(-margin / dx)) + 1;
  last = static_cast<long long>(std::ceil((1 + margin) / dx)) - 1;
}

PointCloud im_cloud(const ImCloudSpec& s) {
  check<ConfigError>(s.dim >= 1 && s.dim <= 3, "the [IM] cloud needs dim 1, 2 or 3, got ", s.dim);
  check<ConfigError>(std::isfinite(s.dx) && s.dx > 0 && s.dx <= 1, "the [IM] cloud needs 0 < dx <= 1, got ", s.dx);
  check<ConfigError>(std::isfinite(s.margin) && s.margin >= 0 && s.margin <= 1, "the [IM] margin H must be in [0, 1], got ", s.margin);
  check<ConfigError>(std::isfinite(s.delta) && s.delta >= 0 && s.delta < 0.5, "the [IM] perturbation must be in [0, 0.5), got ", s.delta);
  long long first = 0, last = 0;
  im_lattice_range(s.dx, s.margin, first, last);
  const long long per_axis = last - first + 1;
  const double total = std::pow(static_cast<double>(per_axis), s.dim);
  check<ConfigError>(total <= 5e8, "the [IM] cloud at dx = ", s.dx, " would have ", total, " particles (limit 5e8)");
  // positions (3 doubles) and tags per particle
  check_memory_estimate(total * (sizeof(Vec3) + sizeof(Tag)), detail::concat("the [IM] cloud of ", total, " particles"),
                        "use a coarser dx (a larger --n or a smaller level)");
  PointCloud c;
  c.dim = s.dim;
  c.spacing = s.dx;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (int k = 0; k < s.dim; ++k) lo[k] = -s.margin, hi[k] = 1 + s.margin;
  c.domain = Domain::box(s.dim, lo, hi);
  const auto n = static_cast<std::size_t>(total);
  c.positions.resize(n, Vec3::Zero());
  c.tags.assign(n, Tag::Interior);
#pragma omp parallel for schedule(static)
  for (long long p = 0; p < static_cast<long long>(n); ++p) {
    long long rest = p;
    Vec3& x = c.positions[static_cast<std::size_t>(p)];
    for (int k = 0; k < s.dim; ++k) {
      const long long i = first + rest % per_axis;
      rest /= per_axis;
      const Real eta = (2 * detail::uniform01(s.seed, static_cast<std::uint64_t>(k), static_cast<std::uint64_t>(p)) - 1) * s.delta;
      x[k] = (static_cast<Real>(i) + eta) * s.dx;
    }
  }
  return c;
}

}  // namespace vrsph
