// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared machinery of the Taylor-corrected methods (FPM, KGF, CSPM, Chen–Beraun, RKPM and
// the [AAR] FPM variants): every one of them solves a small dense square system per
// particle (METHODS §3.0, X4). Here: the equilibrated inverse with its condition number,
// the singular-system policy every such method offers as options, the Taylor basis
// (multi-indices up to degree 2) and kernel derivatives with respect to x_i.
//
// Condition numbers are those of the row/column equilibrated matrix: the raw moment
// matrices mix entries of size h^-d ... h^{2-d}, so their raw condition number grows like
// h^-4 on a perfectly regular cloud and says nothing about singularity.
#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/method.hpp>

namespace vrsph::taylor {

inline constexpr int max_unknowns = 10;  ///< 3D second order: 1 + 3 + 6
using SmallMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, max_unknowns, max_unknowns>;
using SmallVector = Eigen::Matrix<Real, Eigen::Dynamic, 1, Eigen::ColMajor, max_unknowns, 1>;

/// What to do with a particle whose local system is singular or worse conditioned than
/// max_condition: throw NumericalError naming it (default) or warn (row left zero and
/// flagged in Stencil::local_failure, counted as infeasible by the studies).
struct SingularPolicy {
  Real max_condition = 1e12;
  bool warn = false;
};
SingularPolicy read_singular_policy(const MethodOptions& options);
/// Option descriptions for MethodInfo::options: volume=dx|shepard, then (with_policy) the
/// singular-system policy.
std::vector<std::pair<std::string, std::string>> corrected_method_options(bool with_policy = true);
/// value, dx, dy, dz, gradient, laplacian, div-a-grad.
const std::vector<OperatorKind>& every_operator();

/// inverse = M^-1 computed on the equilibrated matrix (rows, then columns scaled to unit
/// max-norm); returns the 1-norm condition estimate of the equilibrated matrix, +inf if
/// M is singular or not finite (inverse is then zero).
Real equilibrated_inverse(const SmallMatrix& M, SmallMatrix& inverse);

/// Call after the per-row loop with Stencil::condition filled for the computed rows:
/// applies the policy (throws NumericalError listing the worst particles, or zeroes the
/// rows and flags them).
void enforce_condition(Stencil& s, const SingularPolicy& policy, const PointCloud& cloud);

/// Multi-indices of degree 1..max_degree (degree 0 first when with_constant), in the
/// order 0, e_1..e_d, then degree-2 lexicographic ((2,0),(1,1),(0,2) in 2D).
std::vector<std::array<int, 3>> multi_indices(int dim, int max_degree, bool with_constant);
/// x^alpha / alpha! (the Taylor coefficient of D^alpha f) or x^alpha when factorial = false.
Real monomial(const Vec3& x, const std::array<int, 3>& alpha, bool factorial);
/// d/dx_k of x^alpha (or x^alpha/alpha!).
Real monomial_derivative(const Vec3& x, const std::array<int, 3>& alpha, int k, bool factorial);

/// Derivatives of W(|x_i - x_j|) with respect to x_i, for the multi-index alpha (degree
/// 0, 1 or 2; METHODS §2.5), at xij = x_i - x_j with r = |xij|.
Real kernel_derivative(const Kernel& k, const Vec3& xij, Real r, const std::array<int, 3>& alpha);

/// W(r), W'(r)/r and W''(r) of one pair, each evaluated once for the derivatives of every
/// multi-index up to max_degree (kernel_derivative from the kernel evaluates it once per index:
/// nine evaluations for a 2D pair's six test functions, where three serve). Same values.
struct PairKernel {
  Real W = 0, dW_over_r = 0, d2W = 0;
};
/// W is evaluated only with_value (a degree-0 index among those wanted); W'/r from degree 1 on,
/// W'' at degree 2.
PairKernel pair_kernel(const Kernel& k, Real r, int max_degree, bool with_value = true);
/// kernel_derivative from the pair's values: the same arithmetic, the same result.
Real kernel_derivative(const PairKernel& kv, const Vec3& xij, Real r, const std::array<int, 3>& alpha);

/// Row i is computed: explicit mask, or every non-ghost particle when the mask is empty.
inline bool wants_row(const PointCloud& cloud, const StencilRequest& req, Index i) {
  return req.rows.empty() ? cloud.tags[static_cast<std::size_t>(i)] != Tag::Ghost
                          : req.rows[static_cast<std::size_t>(i)] != 0;
}

/// The info of a method without a flux form: marks it as reading coefficient_gradient.
inline MethodInfo with_coefficient_gradient(MethodInfo info) {
  info.uses_coefficient_gradient = true;
  return info;
}

/// (∇a)_i for the rule a_i Δ_h u + (∇a)_i·∇_h u (METHODS §3.0): the analytic gradient when
/// the request carries one, else the method's own gradient of a, sum over the neighbours of
/// weight(k) (a_j - a_i), where weight(k) is the Vec3 gradient weight of neighbour k.
template <class GradientWeight>
Vec3 coefficient_gradient(const StencilRequest& req, Index i, std::span<const Index> nbr, int dim,
                          GradientWeight&& weight) {
  Vec3 g = Vec3::Zero();
  if (req.coefficient_gradient) {
    for (int c = 0; c < dim; ++c) g[c] = (*req.coefficient_gradient)(i, c);
    return g;
  }
  const Field& a = *req.coefficient;
  for (std::size_t k = 0; k < nbr.size(); ++k) g += weight(k) * (a[nbr[k]] - a[i]);
  return g;
}

/// Index of the multi-index 2 e_k in a list from multi_indices(), or of e_k.
int position_of(const std::vector<std::array<int, 3>>& list, const std::array<int, 3>& alpha);

/// Volumes v_j for the corrected methods: dx^d (default) or Shepard, from option "volume".
std::vector<Real> method_volumes(const Discretisation& disc, const std::string& volume_option);

}  // namespace vrsph::taylor
