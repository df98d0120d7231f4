// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The moving-least-squares correction shared by the rows exact on polynomials: a given row's
// weights w_ik (one per stencil component and neighbour) get the smallest change δ_ik in the
// kernel-weighted norm Σ_k |δ_ik|² / W(r_ik) that makes the row exact on every monomial of
// degree 1 ... Degree around x_i (3 for the gradient rows, 2 ... 4 for the Hessian rows):
//   δ_ik = W(r_ik) Σ_a P_ak y_a,  (P Ω Pᵀ) y = b - P w,  P_ak = ((x_k - x_i) / h)^α_a,
// b the exact derivative of each monomial at x_i, the diagonal kept at -Σ_k (exact on constants).
// Given rows of zeros this is the moving-least-squares derivative itself (hessian_rows).
// Private to the library: raise_to_cubic_exactness (first derivatives) and hessian_rows use it.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/method.hpp>
#include <vrsph/methods/monomials.hpp>
#include "equilibrated_spd_solve.hpp"

namespace vrsph::cubic_rows {

/// One component of the stencil and the derivative it approximates: the monomial x^α (by its
/// position among monomial_exponents(dim, Degree)) whose derivative at x_i is `value` / h^order in
/// the variables scaled by the support radius h; every other monomial's is 0.
struct Target {
  std::size_t array = 0;
  int monomial = 0;
  Real value = 1;
  int order = 1;  ///< 1 or 2
};

/// Position of the monomial with these exponents among monomial_exponents(dim, degree).
inline int monomial_index(int dim, const std::array<int, 3>& alpha, int degree = 3) {
  const auto e = monomial_exponents(dim, degree);
  for (std::size_t a = 0; a < e.size(); ++a)
    if (e[a] == alpha) return static_cast<int>(a);
  return -1;
}

// The dimension in which there are M monomials of degree 1 ... Degree (the counts differ between
// 1D, 2D and 3D for every Degree used here), and their exponents, at compile time.
template <int M, int Degree>
constexpr int fixed_dimension() {
  for (int dim = 1; dim <= 3; ++dim)
    if (monomial_exponents(dim, Degree).size() == static_cast<std::size_t>(M)) return dim;
  return 0;
}

template <int M, int Degree>
constexpr std::array<std::array<int, 3>, static_cast<std::size_t>(M)> fixed_exponents() {
  std::array<std::array<int, 3>, static_cast<std::size_t>(M)> out{};
  const auto all = monomial_exponents(fixed_dimension<M, Degree>(), Degree);
  for (std::size_t a = 0; a < out.size() && a < all.size(); ++a) out[a] = all[a];
  return out;
}

struct Outcome {
  Index corrected = 0;       ///< rows now exact on the monomials up to Degree
  std::vector<Index> kept;   ///< requested rows left as they were (too few neighbours, ill-conditioned), ascending
};

// q^α from the powers of q's coordinates, α a constant: the product of the powers it needs only.
template <std::array<int, 3> Alpha, int Dim, std::size_t N>
inline Real monomial_value(const std::array<std::array<Real, N>, static_cast<std::size_t>(Dim)>& pw) {
  // (Leaving out the factors q^0 = 1 changes no bit of the product.)
  Real v = Alpha[0] > 0 ? pw[0][static_cast<std::size_t>(Alpha[0])] : Real(1);
  if constexpr (Dim > 1 && Alpha[1] > 0) v *= pw[1][static_cast<std::size_t>(Alpha[1])];
  if constexpr (Dim > 2 && Alpha[2] > 0) v *= pw[2][static_cast<std::size_t>(Alpha[2])];
  return v;
}

// The correction with M monomials (degree 3: 1D 3, 2D 9, 3D 19) as a compile-time size: the per-row
// systems are small, and fixed-size code spared about an eighth of the update step's stencil
// time on 10^5 moving 2D particles against dynamic sizes. C: columns of the right-hand side
// (at least targets.size(); fixed so that the product with A^-1 is unrolled).
//
// The neighbours' monomials are stored monomial by monomial (P row-major, the neighbours
// contiguous), so that every sum over the neighbours (the moment matrix, the residual, the
// correction) is a contiguous dot product or axpy that vectorises. Stored neighbour by neighbour,
// the moment matrix was accumulated in memory one neighbour at a time (a load, add and store per
// entry and neighbour), a quarter of these rows' time (perf, 2.5e5 moving 2D particles).
template <int M, int C, int Degree = 3>
Outcome correct_rows(const Discretisation& disc, const StencilRequest& req, Stencil& s, const std::vector<Target>& targets,
                     Real max_condition) {
  const PointCloud& cloud = disc.cloud;
  // The exponents as constants: each neighbour's monomials are then a few products of its
  // coordinates' powers, where looking the exponents up per monomial and neighbour (and forming
  // the powers of z in 2D) was a quarter of these rows' time (perf, 2.5e5 moving 2D particles).
  static constexpr auto exponents = fixed_exponents<M, Degree>();
  static constexpr int Dim = fixed_dimension<M, Degree>();
  static_assert(Dim >= 1);
  check<ConfigError>(cloud.dim == Dim, "the correction of rows exact on polynomials of degree ", Degree, " with ", M,
                     " monomials is for ", Dim, "D clouds, got ", cloud.dim, "D");
  // The moment matrix's entries Σ_k W_k p_a p_b repeat: p_a p_b is the monomial of exponents
  // α_a + α_b, shared by several pairs (a, b). Only the first pair of each monomial takes a
  // dot product over the neighbours (2D cubic: 25 of the lower triangle's 45, 3D: 80 of 190),
  // the others copy it.
  std::vector<std::pair<int, int>> computed, copied_to, copied_from;
  {
    std::vector<std::pair<std::array<int, 3>, std::pair<int, int>>> seen;
    for (int b = 0; b < M; ++b)
      for (int a = b; a < M; ++a) {
        std::array<int, 3> sum{};
        for (std::size_t c = 0; c < 3; ++c) sum[c] = exponents[static_cast<std::size_t>(a)][c] + exponents[static_cast<std::size_t>(b)][c];
        const auto first = std::find_if(seen.begin(), seen.end(), [&](const auto& e) { return e.first == sum; });
        if (first == seen.end()) {
          seen.push_back({sum, {a, b}});
          computed.emplace_back(a, b);
        } else {
          copied_to.emplace_back(a, b);
          copied_from.push_back(first->second);
        }
      }
  }
  using Square = Eigen::Matrix<Real, M, M>;
  using Columns = Eigen::Matrix<Real, M, C>;
  using Span = Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, 1>>;
  const auto comps = static_cast<Eigen::Index>(targets.size());
  Index corrected = 0;
  std::vector<Index> kept;
#pragma omp parallel reduction(+ : corrected)
  {
    std::vector<Index> kept_here;
    // Per thread, grown to the largest row and never shrunk (no allocation per row).
    std::size_t stride = 0;  // of P and WP: at least the row's neighbour count
    std::vector<Real> P;     // M x stride: p_a(q_k), the neighbours' scaled monomials
    std::vector<Real> WP;    // M x stride: W_k p_a(q_k)
    std::vector<Real> weight;  // W(r_k) / W(0)
    std::vector<Real> work;    // a row's correction δ_k of one component
    std::vector<Index> slots;  // each neighbour's slot in the stencil row
    std::vector<std::size_t> live;  // the neighbours with a weight in the given row
    std::optional<Kernel> ker;
    Columns R;
#pragma omp for schedule(dynamic, 256)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (!row_requested(cloud, req, i) || (!s.local_failure.empty() && s.local_failure[si])) continue;
      const auto nbr = disc.neighbours.of(i);
      const auto dist = disc.neighbours.distances_of(i);
      const Real h = disc.neighbours.radius(i);
      // The kernel changes only with the support radius (a pow per construction).
      if (!ker || ker->support() != h) ker = disc.kernel_at(i);
      const Real w0 = ker->W(0);
      const auto n = static_cast<Eigen::Index>(nbr.size());
      if (stride < nbr.size()) {
        stride = nbr.size();
        P.resize(static_cast<std::size_t>(M) * stride);
        WP.resize(static_cast<std::size_t>(M) * stride);
        weight.resize(stride);
        work.resize(stride);
        slots.resize(stride);
        live.resize(stride);
      }
      // Neighbours inside the support: a Verlet list holds some beyond it, where every row's
      // weight is zero. (Giving the correction to the nearer ones only, r < 0.8 h, cost 3D rows
      // a third of their accuracy and 2D rows near walls a factor 7: measured, not kept.)
      // Products with reciprocals rather than five divisions per neighbour (the scaled offset's
      // three, the weight's): out-of-order execution hid the divisions, the update's time did not
      // change measurably (1.6e5 moving 2D particles), but it is the cheaper form.
      Eigen::Index K = 0, near = 0;
      const Vec3& xi = cloud.positions[si];
      const Real inv_h = 1 / h, inv_w0 = 1 / w0;
      for (Eigen::Index k = 0; k < n; ++k) {
        const Real r = dist[static_cast<std::size_t>(k)];
        if (!(r < h)) continue;
        const Vec3 q = (disc.neighbour_position(i, static_cast<Index>(k)) - xi) * inv_h;
        std::array<std::array<Real, static_cast<std::size_t>(Degree) + 1>, static_cast<std::size_t>(Dim)> pw;  // q_c^0 ... q_c^Degree
        for (std::size_t c = 0; c < static_cast<std::size_t>(Dim); ++c) {
          pw[c][0] = 1;
          for (std::size_t e = 1; e <= static_cast<std::size_t>(Degree); ++e) pw[c][e] = pw[c][e - 1] * q[static_cast<int>(c)];
        }
        const auto sk = static_cast<std::size_t>(K);
        [&]<std::size_t... A>(std::index_sequence<A...>) {
          ((P[A * stride + sk] = monomial_value<exponents[A], Dim>(pw)), ...);
        }(std::make_index_sequence<static_cast<std::size_t>(M)>{});
        const Real w = ker->W(r) * inv_w0;
        weight[sk] = w;
        near += w > 0 ? 1 : 0;
        slots[sk] = neighbour_slot(s, i, static_cast<Index>(k));
        ++K;
      }
      if (near < M) {
        kept_here.push_back(i);
        continue;
      }
      const auto row = [&](const std::vector<Real>& m, int a) { return Span(m.data() + static_cast<std::size_t>(a) * stride, K); };
      for (int a = 0; a < M; ++a) {
        const auto off = static_cast<std::size_t>(a) * stride;
        for (std::size_t k = 0; k < static_cast<std::size_t>(K); ++k) WP[off + k] = weight[k] * P[off + k];
      }
      Square A;  // Σ_k W_k p_k p_k^T, its lower triangle
      for (const auto& [a, b] : computed) A(a, b) = row(P, a).dot(row(WP, b));
      for (std::size_t e = 0; e < copied_to.size(); ++e)
        A(copied_to[e].first, copied_to[e].second) = A(copied_from[e].first, copied_from[e].second);
      // R = b - P w per component. The given rows are sparse: VRSPH's keep a weight for about
      // one neighbour per moment condition (9 of the 2D support's 28), the Hessian's none. The
      // sums run over the neighbours with a weight in some component, listed without a branch
      // per neighbour; the terms left out are products with zero, which change no bit of a sum
      // that starts at +0.
      std::size_t weighted = 0;
      for (std::size_t k = 0; k < static_cast<std::size_t>(K); ++k) {
        bool any = false;
        for (const Target& t : targets) any |= s.values[t.array][static_cast<std::size_t>(slots[k])] != 0;
        live[weighted] = k;
        weighted += any ? 1 : 0;
      }
      R.setZero();
      for (Eigen::Index c = 0; c < comps; ++c) {
        const Target& t = targets[static_cast<std::size_t>(c)];
        const std::vector<Real>& g = s.values[t.array];
        // The M sums side by side over the neighbours (one pass over P, each weight loaded once).
        std::array<Real, static_cast<std::size_t>(M)> pg{};
        for (std::size_t e = 0; e < weighted; ++e) {
          const std::size_t k = live[e];
          const Real gk = g[static_cast<std::size_t>(slots[k])];
          for (std::size_t a = 0; a < static_cast<std::size_t>(M); ++a) pg[a] += P[a * stride + k] * gk;
        }
        for (int a = 0; a < M; ++a) R(a, c) = -pg[static_cast<std::size_t>(a)];
        R(t.monomial, c) += t.order == 1 ? t.value / h : t.value / (h * h);
      }
      Columns Y;
      if (!equilibrated_spd_solve<M, C>(A, R, comps, Y, max_condition)) {
        kept_here.push_back(i);
        continue;
      }
      // δ_k = W_k p_k · y: per neighbour the M products summed in a register (M is a
      // compile-time constant: the sum unrolls), one pass over WP; as M axpy passes over a
      // scratch row it loaded and stored that row M times.
      const auto diag = static_cast<std::size_t>(s.diag[si]);
      for (Eigen::Index c = 0; c < comps; ++c) {
        std::vector<Real>& g = s.values[targets[static_cast<std::size_t>(c)].array];
        std::array<Real, static_cast<std::size_t>(M)> y{};
        for (int a = 0; a < M; ++a) y[static_cast<std::size_t>(a)] = Y(a, c);
        for (std::size_t k = 0; k < static_cast<std::size_t>(K); ++k) {
          Real d = 0;
          for (std::size_t a = 0; a < static_cast<std::size_t>(M); ++a) d += y[a] * WP[a * stride + k];
          work[k] = d;
        }
        Real added = 0;
        for (std::size_t k = 0; k < static_cast<std::size_t>(K); ++k) {
          g[static_cast<std::size_t>(slots[k])] += work[k];
          added += work[k];
        }
        g[diag] -= added;
      }
      ++corrected;
    }
#pragma omp critical(vrsph_cubic_rows_kept)
    kept.insert(kept.end(), kept_here.begin(), kept_here.end());
  }
  std::sort(kept.begin(), kept.end());
  return {corrected, std::move(kept)};
}

}  // namespace vrsph::cubic_rows
