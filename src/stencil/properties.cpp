// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/properties.hpp>
#include "../core/reachability.hpp"

namespace vrsph {

Field row_sums(const Stencil& s, int component) {
  check<InputError>(component >= 0 && component < s.components(), "row_sums: component ", component, " out of range");
  const auto& v = s.values[static_cast<std::size_t>(component)];
  Field out = Field::Zero(s.rows());
  for (Index i = 0; i < s.rows(); ++i)
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) out[i] += v[static_cast<std::size_t>(k)];
  return out;
}

std::string MMatrixReport::summary() const {
  if (is_m_matrix()) return detail::concat("-L is an M-matrix (", rows, " unknown rows, weakly chained diagonally dominant)");
  std::string s = "-L is NOT an M-matrix:";
  if (!z_matrix) s += detail::concat(" ", positive_offdiagonal, " off-diagonal entries of the wrong sign;");
  if (!diagonally_dominant) s += detail::concat(" ", non_dominant_rows, " rows not diagonally dominant;");
  if (!chained) s += detail::concat(" ", unreachable.size(), " rows not connected to a strictly dominant (boundary) row;");
  if (first_violation >= 0) s += detail::concat(" first at particle ", first_violation);
  return s;
}

MMatrixReport check_m_matrix(const Stencil& s, std::span<const char> unknown, Real tol) {
  return check_m_matrix(s, unknown, tol, unknown,
                        [](std::span<const Index> offsets, std::span<const Index> targets, std::vector<char> seeds) {
                          return detail::reaching(offsets, targets, std::move(seeds));
                        });
}

MMatrixReport check_m_matrix(const Stencil& s, std::span<const char> unknown, Real tol, std::span<const char> rows,
                             const ChainClosure& close) {
  check<InputError>(static_cast<Index>(unknown.size()) == s.rows(), "check_m_matrix: mask has ", unknown.size(),
                    " entries for ", s.rows(), " rows (size mismatch)");
  check<InputError>(rows.size() == unknown.size(), "check_m_matrix: row mask has ", rows.size(), " entries for ",
                    unknown.size(), " particles");
  check<ConfigError>(s.components() == 1, "check_m_matrix needs a scalar operator, got ", to_string(s.kind));
  const auto& v = s.values[0];
  MMatrixReport rep;
  const Index n = s.rows();
  std::vector<char> strict(static_cast<std::size_t>(n), 0);
  auto flag = [&](Index i) {
    if (rep.first_violation < 0) rep.first_violation = i;
  };
  for (Index i = 0; i < n; ++i) {
    if (!rows[static_cast<std::size_t>(i)]) continue;
    ++rep.rows;
    Real scale = 0;
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) scale = std::max(scale, std::abs(v[static_cast<std::size_t>(k)]));
    const Real eps = tol * scale;
    const Real diag = -v[static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])];  // diagonal of -L
    Real off = 0;
    bool row_z = true;
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
      const Index j = s.col[static_cast<std::size_t>(k)];
      if (j == i || !unknown[static_cast<std::size_t>(j)]) continue;
      const Real lij = v[static_cast<std::size_t>(k)];
      if (lij < -eps) {
        ++rep.positive_offdiagonal;
        row_z = false;
      }
      off += std::abs(lij);
    }
    if (!row_z) {
      rep.z_matrix = false;
      flag(i);
    }
    if (diag < off - eps) {
      ++rep.non_dominant_rows;
      rep.diagonally_dominant = false;
      flag(i);
    } else if (diag > off + eps) {
      strict[static_cast<std::size_t>(i)] = 1;
    }
  }
  // Reachability: row i "reaches" j if L_ij != 0; search backwards from the strictly
  // dominant rows.
  std::vector<Index> offsets(static_cast<std::size_t>(n) + 1, 0), targets;
  for (Index i = 0; i < n; ++i) {
    if (rows[static_cast<std::size_t>(i)])
      for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
        const Index j = s.col[static_cast<std::size_t>(k)];
        if (j != i && unknown[static_cast<std::size_t>(j)] && v[static_cast<std::size_t>(k)] != 0) targets.push_back(j);
      }
    offsets[static_cast<std::size_t>(i) + 1] = static_cast<Index>(targets.size());
  }
  const std::vector<char> reached = close(offsets, targets, std::move(strict));
  for (Index i = 0; i < n; ++i)
    if (rows[static_cast<std::size_t>(i)] && !reached[static_cast<std::size_t>(i)]) {
      rep.unreachable.push_back(i);
      rep.chained = false;
      flag(i);
    }
  return rep;
}

LocalResidualSummary summarise_local_residuals(const Stencil& s, std::span<const char> rows, Real tolerance,
                                               std::size_t max_listed) {
  LocalResidualSummary out;
  if (s.residual.empty() && s.local_failure.empty()) return out;
  check<InputError>(static_cast<Index>(rows.size()) == s.rows(), "local residual summary: mask has ", rows.size(),
                    " entries for ", s.rows(), " rows (size mismatch)");
  const Real bnorm = std::sqrt(static_cast<Real>(s.dim));
  std::vector<std::pair<Real, Index>> bad;
  for (Index i = 0; i < s.rows(); ++i) {
    if (!rows[static_cast<std::size_t>(i)]) continue;
    const Real r = s.residual.empty() ? 0 : s.residual[static_cast<std::size_t>(i)] / bnorm;
    const bool failed = !s.local_failure.empty() && s.local_failure[static_cast<std::size_t>(i)];
    if (!failed) out.max_relative = std::max(out.max_relative, r);
    if (r > tolerance || failed) bad.emplace_back(failed ? std::numeric_limits<Real>::infinity() : r, i);
  }
  out.infeasible = static_cast<Index>(bad.size());
  const std::size_t keep = std::min(max_listed, bad.size());
  std::partial_sort(bad.begin(), bad.begin() + static_cast<std::ptrdiff_t>(keep), bad.end(), std::greater<>());
  out.worst.assign(bad.begin(), bad.begin() + static_cast<std::ptrdiff_t>(keep));
  return out;
}

namespace {
// Exact value at x_i of the operator applied to (x - x_i)^alpha, component c.
Real exact_on_centred_monomial(OperatorKind kind, const std::array<int, 3>& a, int c, int dim) {
  const int deg = a[0] + a[1] + a[2];
  switch (kind) {
    case OperatorKind::Value: return deg == 0 ? 1 : 0;
    case OperatorKind::Dx:
    case OperatorKind::Dy:
    case OperatorKind::Dz: {
      const int k = kind == OperatorKind::Dx ? 0 : kind == OperatorKind::Dy ? 1 : 2;
      return deg == 1 && a[static_cast<std::size_t>(k)] == 1 ? 1 : 0;
    }
    case OperatorKind::Gradient: return deg == 1 && a[static_cast<std::size_t>(c)] == 1 ? 1 : 0;
    case OperatorKind::Laplacian: return deg == 2 && (a[0] == 2 || a[1] == 2 || a[2] == 2) ? 2 : 0;
    case OperatorKind::Hessian: {  // ∂_b ∂_c of x^α: 2 for x_b², 1 for x_b x_c (b ≠ c)
      const auto [b, e] = hessian_axes(c, dim);
      std::array<int, 3> pair{};
      ++pair[static_cast<std::size_t>(b)];
      ++pair[static_cast<std::size_t>(e)];
      return a == pair ? (b == e ? 2 : 1) : 0;
    }
    case OperatorKind::DivAGrad: break;
  }
  throw ConfigError(detail::concat("monomial residuals are not defined for operator ", to_string(kind)));
}
}  // namespace

std::vector<MonomialResidual> monomial_residuals(const Stencil& s, const PointCloud& cloud,
                                                 std::span<const Real> row_scale, int max_degree,
                                                 std::span<const char> rows) {
  check<ConfigError>(s.kind != OperatorKind::DivAGrad, "monomial residuals are not defined for div-a-grad");
  check<InputError>(s.rows() == cloud.size() && static_cast<Index>(rows.size()) == s.rows() &&
                        static_cast<Index>(row_scale.size()) == s.rows(),
                    "monomial_residuals: stencil, cloud, scale and row mask sizes differ");
  check<InputError>(max_degree >= 0 && max_degree <= 6, "monomial degree must be in 0..6, got ", max_degree);
  const int order = traits(s.kind).derivative_order;
  std::vector<MonomialResidual> out;
  for (int deg = 0; deg <= max_degree; ++deg)
    for (int a0 = deg; a0 >= 0; --a0)
      for (int a1 = deg - a0; a1 >= 0; --a1) {
        const std::array<int, 3> a{a0, a1, deg - a0 - a1};
        if ((s.dim < 2 && a[1] > 0) || (s.dim < 3 && a[2] > 0)) continue;
        Real worst = 0;
        for (Index i = 0; i < s.rows(); ++i) {
          if (!rows[static_cast<std::size_t>(i)]) continue;
          const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
          Real norm2 = 0;
          for (int c = 0; c < s.components(); ++c) {
            const auto& v = s.values[static_cast<std::size_t>(c)];
            Real acc = 0;
            for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
              const Vec3 d = cloud.positions[static_cast<std::size_t>(s.col[static_cast<std::size_t>(k)])] - xi;
              acc += v[static_cast<std::size_t>(k)] * std::pow(d[0], a[0]) * std::pow(d[1], a[1]) * std::pow(d[2], a[2]);
            }
            const Real r = (acc - exact_on_centred_monomial(s.kind, a, c, s.dim)) *
                           std::pow(row_scale[static_cast<std::size_t>(i)], order - deg);
            norm2 += r * r;
          }
          worst = std::max(worst, std::sqrt(norm2));
        }
        out.push_back({a, worst});
      }
  return out;
}

Real spectral_radius(const Stencil& s, std::span<const char> active, int iterations) {
  check<ConfigError>(iterations > 0, "spectral_radius: iterations must be positive, got ", iterations);
  const Index n = std::min<Index>(s.rows(), static_cast<Index>(active.size()));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), y(n);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // a fixed start: the same estimate every run
  for (Index i = 0; i < n; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    if (active[static_cast<std::size_t>(i)]) x[i] = 0.5 + static_cast<double>(state >> 11) * 0x1.0p-53;
  }
  const std::vector<Real>& v = s.values[0];
  Real rho = 0;
  for (int step = 0; step < iterations; ++step) {
    const Real norm = x.norm();
    if (!(norm > 0)) return 0;
    x /= norm;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      Real sum = 0;
      if (active[static_cast<std::size_t>(i)])
        for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
          const Index j = s.col[static_cast<std::size_t>(k)];
          if (j < n && active[static_cast<std::size_t>(j)]) sum += v[static_cast<std::size_t>(k)] * x[j];
        }
      y[i] = sum;
    }
    rho = y.norm();
    std::swap(x, y);
  }
  return rho;
}

}  // namespace vrsph
