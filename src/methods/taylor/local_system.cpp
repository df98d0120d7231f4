// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/sph/sph.hpp>
#include <vrsph/methods/taylor/local_system.hpp>

namespace vrsph::taylor {

SingularPolicy read_singular_policy(const MethodOptions& o) {
  SingularPolicy p;
  p.max_condition = o.get_real("max_condition", 1e12);
  check<ConfigError>(p.max_condition > 1, "option max_condition must be > 1, got ", p.max_condition);
  p.warn = o.get_choice("on_singular", "error", {"error", "warn"}) == "warn";
  return p;
}

std::vector<std::pair<std::string, std::string>> corrected_method_options(bool with_policy) {
  std::vector<std::pair<std::string, std::string>> o{{"volume", "dx (v_j = dx^d, default) | shepard (v_j = 1/sum_k W_jk)"}};
  if (with_policy) {
    o.emplace_back("max_condition", "largest accepted condition number of a local system (default 1e12)");
    o.emplace_back("on_singular", "error (default: name the particle and stop) | warn (leave the row zero and flag it)");
  }
  return o;
}

const std::vector<OperatorKind>& every_operator() {
  static const std::vector<OperatorKind> ops{OperatorKind::Value,    OperatorKind::Dx,       OperatorKind::Dy,
                                             OperatorKind::Dz,       OperatorKind::Gradient, OperatorKind::Laplacian,
                                             OperatorKind::DivAGrad};
  return ops;
}

Real equilibrated_inverse(const SmallMatrix& M, SmallMatrix& inverse) {
  const auto n = M.rows();
  inverse.setZero(n, n);
  if (!M.allFinite()) return std::numeric_limits<Real>::infinity();
  SmallVector r(n), c(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Real m = M.row(i).cwiseAbs().maxCoeff();
    if (m == 0) return std::numeric_limits<Real>::infinity();
    r[i] = 1 / m;
  }
  SmallMatrix E = r.asDiagonal() * M;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Real m = E.col(j).cwiseAbs().maxCoeff();
    if (m == 0) return std::numeric_limits<Real>::infinity();
    c[j] = 1 / m;
  }
  E = E * c.asDiagonal();
  const Eigen::PartialPivLU<SmallMatrix> lu(E);
  const Real rcond = lu.rcond();
  if (!(rcond > 0) || !std::isfinite(rcond)) return std::numeric_limits<Real>::infinity();
  // M = R^-1 E C^-1  =>  M^-1 = C E^-1 R
  inverse = c.asDiagonal() * lu.inverse() * r.asDiagonal();
  if (!inverse.allFinite()) {
    inverse.setZero(n, n);
    return std::numeric_limits<Real>::infinity();
  }
  return 1 / rcond;
}

void enforce_condition(Stencil& s, const SingularPolicy& policy, const PointCloud& cloud) {
  if (s.condition.empty()) return;
  std::vector<std::pair<Real, Index>> bad;
  for (Index i = 0; i < s.rows(); ++i) {
    const Real c = s.condition[static_cast<std::size_t>(i)];
    if (!(c <= policy.max_condition)) bad.emplace_back(std::isnan(c) ? std::numeric_limits<Real>::infinity() : c, i);
  }
  if (bad.empty()) return;
  std::sort(bad.begin(), bad.end(), std::greater<>());
  if (!policy.warn) {
    std::string list;
    for (std::size_t k = 0; k < std::min<std::size_t>(5, bad.size()); ++k) {
      const Vec3& x = cloud.positions[static_cast<std::size_t>(bad[k].second)];
      list += detail::concat(k ? "; " : "", "particle ", bad[k].second, " at (", x[0], ", ", x[1], ", ", x[2],
                             ") condition ", bad[k].first);
    }
    throw NumericalError(detail::concat(s.method, ": ", bad.size(), " particle(s) with a singular or ill-conditioned ",
                                        "local system (condition > ", policy.max_condition, "): ", list,
                                        ". Too few or one-sided neighbours: increase h, or pass on_singular=warn"));
  }
  if (s.local_failure.empty()) s.local_failure.assign(static_cast<std::size_t>(s.rows()), 0);
  for (const auto& [c, i] : bad) {
    s.local_failure[static_cast<std::size_t>(i)] = 1;
    for (auto& v : s.values)
      for (Index k = s.row_begin(i); k < s.row_end(i); ++k) v[static_cast<std::size_t>(k)] = 0;
  }
}

std::vector<std::array<int, 3>> multi_indices(int dim, int max_degree, bool with_constant) {
  std::vector<std::array<int, 3>> out;
  if (with_constant) out.push_back({0, 0, 0});
  for (int k = 0; k < dim; ++k) {
    std::array<int, 3> a{0, 0, 0};
    a[static_cast<std::size_t>(k)] = 1;
    out.push_back(a);
  }
  if (max_degree >= 2)
    for (int k = 0; k < dim; ++k)
      for (int l = k; l < dim; ++l) {
        std::array<int, 3> a{0, 0, 0};
        a[static_cast<std::size_t>(k)] += 1;
        a[static_cast<std::size_t>(l)] += 1;
        out.push_back(a);
      }
  return out;
}

namespace {
Real power(Real x, int p) { return p == 0 ? 1 : p == 1 ? x : p == 2 ? x * x : x * x * x; }
Real factorial(int p) { return p == 3 ? 6 : p == 2 ? 2 : 1; }
}  // namespace

Real monomial(const Vec3& x, const std::array<int, 3>& a, bool fact) {
  Real v = 1;
  for (int k = 0; k < 3; ++k) {
    const int p = a[static_cast<std::size_t>(k)];
    v *= power(x[k], p) / (fact ? factorial(p) : 1);
  }
  return v;
}

Real monomial_derivative(const Vec3& x, const std::array<int, 3>& a, int k, bool fact) {
  const int p = a[static_cast<std::size_t>(k)];
  if (p == 0) return 0;
  Real v = 1;
  for (int m = 0; m < 3; ++m) {
    const int q = a[static_cast<std::size_t>(m)];
    if (m == k)
      v *= p * power(x[m], q - 1) / (fact ? factorial(q) : 1);
    else
      v *= power(x[m], q) / (fact ? factorial(q) : 1);
  }
  return v;
}

PairKernel pair_kernel(const Kernel& ker, Real r, int max_degree, bool with_value) {
  PairKernel kv;
  if (with_value) kv.W = ker.W(r);
  if (max_degree >= 1) kv.dW_over_r = ker.dW_over_r(r);
  if (max_degree >= 2) kv.d2W = ker.d2W(r);
  return kv;
}

Real kernel_derivative(const PairKernel& kv, const Vec3& xij, Real r, const std::array<int, 3>& a) {
  const int deg = a[0] + a[1] + a[2];
  if (deg == 0) return kv.W;
  int k = -1, l = -1;
  for (int m = 0; m < 3; ++m)
    for (int c = 0; c < a[static_cast<std::size_t>(m)]; ++c) (k < 0 ? k : l) = m;
  if (deg == 1) return kv.dW_over_r * xij[k];
  check<ConfigError>(deg == 2, "kernel derivatives of order > 2 are not provided");
  const Real delta = k == l ? 1 : 0;
  if (r == 0) return kv.d2W * delta;
  const Real ek = xij[k] / r, el = xij[l] / r;
  return kv.d2W * ek * el + kv.dW_over_r * (delta - ek * el);
}

Real kernel_derivative(const Kernel& ker, const Vec3& xij, Real r, const std::array<int, 3>& a) {
  const int deg = a[0] + a[1] + a[2];
  check<ConfigError>(deg <= 2, "kernel derivatives of order > 2 are not provided");
  return kernel_derivative(pair_kernel(ker, r, deg, deg == 0), xij, r, a);  // only what this index reads
}

int position_of(const std::vector<std::array<int, 3>>& list, const std::array<int, 3>& alpha) {
  const auto it = std::find(list.begin(), list.end(), alpha);
  check<ConfigError>(it != list.end(), "internal: multi-index not in the Taylor basis");
  return static_cast<int>(it - list.begin());
}

std::vector<Real> method_volumes(const Discretisation& disc, const std::string& volume) {
  return sph_volumes(disc, volume == "shepard" ? SphVolume::Shepard : SphVolume::Spacing);
}

}  // namespace vrsph::taylor
