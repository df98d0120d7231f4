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
#include "../core/compiler_hints.hpp"
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

// The moment matrix Σ_k W_k p_k p_k^T: its entry (a, b) is Σ_k W_k q_k^(α_a + α_b), and the
// exponent sums α_a + α_b repeat (2D cubic: 25 distinct among the lower triangle's 45, 3D: 80
// among 190). `sums` lists the distinct ones, `entry[a][b]` (a >= b) the one of each entry.
template <int M, int Degree>
struct MomentSums {
  using Exponent = std::array<int, 3>;
  static constexpr auto exponents = fixed_exponents<M, Degree>();
  static constexpr int dim = fixed_dimension<M, Degree>();
  // An exponent sum as one integer below 16^3 (each exponent is below 16), and each sum's place
  // among the distinct ones by a table over those integers: a search of the distinct sums per
  // entry exceeded clang's constant-evaluation limit at M = 34.
  static constexpr int key(std::size_t a, std::size_t b) {
    return ((exponents[a][0] + exponents[b][0]) * 16 + exponents[a][1] + exponents[b][1]) * 16 + exponents[a][2] +
           exponents[b][2];
  }
  struct Distinct {
    std::array<int, 4096> place{};      // by key: its index among the distinct sums, or -1
    std::array<int, 4096> key_of{};     // by index: the key
    std::size_t count = 0;
  };
  static constexpr Distinct distinct() {
    Distinct d;
    d.place.fill(-1);
    for (std::size_t b = 0; b < static_cast<std::size_t>(M); ++b)
      for (std::size_t a = b; a < static_cast<std::size_t>(M); ++a) {
        const int k = key(a, b);
        if (d.place[static_cast<std::size_t>(k)] < 0) {
          d.place[static_cast<std::size_t>(k)] = static_cast<int>(d.count);
          d.key_of[d.count++] = k;
        }
      }
    return d;
  }
  static constexpr std::size_t count = distinct().count;
  static constexpr std::array<Exponent, count> sums = [] {
    const Distinct d = distinct();
    std::array<Exponent, count> out{};
    for (std::size_t i = 0; i < count; ++i) out[i] = {d.key_of[i] / 256, (d.key_of[i] / 16) % 16, d.key_of[i] % 16};
    return out;
  }();
  static constexpr std::array<std::array<std::size_t, static_cast<std::size_t>(M)>, static_cast<std::size_t>(M)> entry = [] {
    const Distinct d = distinct();
    std::array<std::array<std::size_t, static_cast<std::size_t>(M)>, static_cast<std::size_t>(M)> out{};
    for (std::size_t b = 0; b < static_cast<std::size_t>(M); ++b)
      for (std::size_t a = b; a < static_cast<std::size_t>(M); ++a)
        out[a][b] = static_cast<std::size_t>(d.place[static_cast<std::size_t>(key(a, b))]);
    return out;
  }();
};

// The per-neighbour helpers below are forced inline, and their loops written as folds over
// constant indices: a call or a loop left in the body of a loop over the neighbours kept the
// compiler from vectorising that loop (-fopt-info-vec).

// p[e] = x^e, e = 0 ... Top, by repeated products.
template <std::size_t Top>
VRSPH_ALWAYS_INLINE inline void powers_of(Real x, std::array<Real, Top + 1>& p) {
  p[0] = 1;
  [&]<std::size_t... E>(std::index_sequence<E...>) VRSPH_ALWAYS_INLINE { ((p[E + 1] = p[E] * x), ...); }(std::make_index_sequence<Top>{});
}

// The powers q_c^0 ... q_c^Top of neighbour k's scaled offset, per coordinate.
template <int Dim, std::size_t Top>
VRSPH_ALWAYS_INLINE inline std::array<std::array<Real, Top + 1>, static_cast<std::size_t>(Dim)> offset_powers(
    std::array<const Real*, 3> q, std::size_t k) {
  std::array<std::array<Real, Top + 1>, static_cast<std::size_t>(Dim)> pw;
  [&]<std::size_t... Cs>(std::index_sequence<Cs...>) VRSPH_ALWAYS_INLINE { (powers_of<Top>(q[Cs][k], pw[Cs]), ...); }(
      std::make_index_sequence<static_cast<std::size_t>(Dim)>{});
  return pw;
}

// Sums First ... First + G - 1 of MomentSums<M, Degree> over the K neighbours (q: their scaled
// offsets by coordinate, w: their weights), G of them side by side in one pass: every neighbour's
// powers are formed once for the G sums, and the sums are independent chains of adds the compiler
// spreads over vector lanes (neighbours) and registers (sums). As one dot product per sum over
// stored monomials, each sum waited on its own chain of adds, and storing the monomials and their
// weighted copies cost as much again (2.5·10⁵ moving 2D particles, perf).
template <int M, int Degree, std::size_t First, std::size_t G>
VRSPH_ALWAYS_INLINE inline void moment_sums(std::array<const Real*, 3> q, const Real* w, std::size_t K, Real* out) {
  using S = MomentSums<M, Degree>;
  constexpr std::size_t top = 2 * static_cast<std::size_t>(Degree);
  std::array<Real, G> acc{};
  for (std::size_t k = 0; k < K; ++k) {
    const auto pw = offset_powers<S::dim, top>(q, k);
    const Real wk = w[k];
    [&]<std::size_t... E>(std::index_sequence<E...>) VRSPH_ALWAYS_INLINE {
      ((acc[E] += wk * monomial_value<S::sums[First + E], S::dim>(pw)), ...);
    }(std::make_index_sequence<G>{});
  }
  for (std::size_t e = 0; e < G; ++e) out[First + e] = acc[e];
}

// Every sum of MomentSums<M, Degree>, sixteen to a pass (more than the registers hold spill).
template <int M, int Degree, std::size_t First = 0>
VRSPH_ALWAYS_INLINE inline void all_moment_sums(std::array<const Real*, 3> q, const Real* w, std::size_t K, Real* out) {
  constexpr std::size_t count = MomentSums<M, Degree>::count;
  if constexpr (First < count) {
    constexpr std::size_t g = std::min<std::size_t>(16, count - First);
    moment_sums<M, Degree, First, g>(q, w, K, out);
    all_moment_sums<M, Degree, First + g>(q, w, K, out);
  }
}

// Σ_a u_a v_a in index order, unrolled.
template <std::size_t N>
VRSPH_ALWAYS_INLINE inline Real fixed_dot(const std::array<Real, N>& u, const std::array<Real, N>& v) {
  return [&]<std::size_t... A>(std::index_sequence<A...>) VRSPH_ALWAYS_INLINE {
    Real d = 0;
    ((d += u[A] * v[A]), ...);
    return d;
  }(std::make_index_sequence<N>{});
}

// The monomials p_a(q_k), a < M, of neighbour k.
template <int M, int Degree>
VRSPH_ALWAYS_INLINE inline std::array<Real, static_cast<std::size_t>(M)> monomials_at(std::array<const Real*, 3> q,
                                                                                     std::size_t k) {
  using S = MomentSums<M, Degree>;
  const auto pw = offset_powers<S::dim, static_cast<std::size_t>(Degree)>(q, k);
  return [&]<std::size_t... A>(std::index_sequence<A...>) VRSPH_ALWAYS_INLINE {
    return std::array<Real, static_cast<std::size_t>(M)>{monomial_value<S::exponents[A], S::dim>(pw)...};
  }(std::make_index_sequence<static_cast<std::size_t>(M)>{});
}

// The correction with M monomials (degree 3: 1D 3, 2D 9, 3D 19) as a compile-time size: the per-row
// systems are small, and fixed-size code spared about an eighth of the update step's stencil
// time on 10^5 moving 2D particles against dynamic sizes. C: columns of the right-hand side
// (at least targets.size(); fixed so that the product with A^-1 is unrolled).
//
// Per row only the neighbours' scaled offsets (by coordinate, the neighbours contiguous) and
// weights are stored; the moment sums, the residual and the correction form the monomials from
// them where they need them, in passes that vectorise over the neighbours.
template <int M, int C, int Degree = 3>
Outcome correct_rows(const Discretisation& disc, const StencilRequest& req, Stencil& s, const std::vector<Target>& targets,
                     Real max_condition) {
  const PointCloud& cloud = disc.cloud;
  using Sums = MomentSums<M, Degree>;
  constexpr int Dim = Sums::dim;
  static_assert(Dim >= 1);
  constexpr auto m = static_cast<std::size_t>(M), nc = static_cast<std::size_t>(C);
  check<ConfigError>(cloud.dim == Dim, "the correction of rows exact on polynomials of degree ", Degree, " with ", M,
                     " monomials is for ", Dim, "D clouds, got ", cloud.dim, "D");
  check<ConfigError>(targets.size() <= nc, "the correction of rows exact on polynomials takes at most ", C,
                     " components, got ", targets.size());
  using Square = Eigen::Matrix<Real, M, M>;
  using Columns = Eigen::Matrix<Real, M, C>;
  const std::size_t comps = targets.size();
  Index corrected = 0;
  std::vector<Index> kept;
#pragma omp parallel reduction(+ : corrected)
  {
    std::vector<Index> kept_here;
    // Per thread, grown to the largest row and never shrunk (no allocation per row).
    std::size_t stride = 0;  // of offsets and work: at least the row's neighbour count
    std::vector<Real> offsets;  // Dim x stride: the scaled offsets (x_k - x_i) / h by coordinate
    std::vector<Real> weight;   // W(r_k) / W(0)
    std::vector<Real> work;     // C x stride: a row's correction δ_k per component
    std::vector<Index> slots;   // each neighbour's slot in the stencil row
    std::vector<std::size_t> live;  // the neighbours with a weight in the given row
    std::array<Real, Sums::count> moment{};
    std::optional<Kernel> ker;
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
      const std::size_t n = nbr.size();
      if (stride < n) {
        stride = n;
        offsets.resize(static_cast<std::size_t>(Dim) * stride);
        weight.resize(stride);
        work.resize(nc * stride);
        slots.resize(stride);
        live.resize(stride);
      }
      const std::array<const Real*, 3> q{offsets.data(), offsets.data() + (Dim > 1 ? stride : 0),
                                         offsets.data() + (Dim > 2 ? 2 * stride : 0)};
      // Neighbours inside the support: a Verlet list holds some beyond it, where every row's
      // weight is zero. (Giving the correction to the nearer ones only, r < 0.8 h, cost 3D rows
      // a third of their accuracy and 2D rows near walls a factor 7: measured, not kept.)
      // Products with reciprocals rather than divisions per neighbour.
      std::size_t K = 0, near = 0;
      const Vec3& xi = cloud.positions[si];
      const Real inv_h = 1 / h, inv_w0 = 1 / w0;
      for (std::size_t k = 0; k < n; ++k) {
        const Real r = dist[k];
        if (!(r < h)) continue;
        const Vec3 d = (disc.neighbour_position(i, static_cast<Index>(k)) - xi) * inv_h;
        for (std::size_t c = 0; c < static_cast<std::size_t>(Dim); ++c) offsets[c * stride + K] = d[static_cast<int>(c)];
        const Real w = ker->W(r) * inv_w0;
        weight[K] = w;
        near += w > 0 ? 1 : 0;
        slots[K] = neighbour_slot(s, i, static_cast<Index>(k));
        ++K;
      }
      if (near < m) {
        kept_here.push_back(i);
        continue;
      }
      all_moment_sums<M, Degree>(q, weight.data(), K, moment.data());
      Square A;  // Σ_k W_k p_k p_k^T, its lower triangle
      for (std::size_t b = 0; b < m; ++b)
        for (std::size_t a = b; a < m; ++a) A(static_cast<int>(a), static_cast<int>(b)) = moment[Sums::entry[a][b]];
      // R = b - P w per component. The given rows are sparse: VRSPH's keep a weight for about
      // one neighbour per moment condition (9 of the 2D support's 28), the Hessian's none. The
      // sums run over the neighbours with a weight in some component, listed without a branch
      // per neighbour; the terms left out are products with zero, which change no bit of a sum
      // that starts at +0.
      std::size_t weighted = 0;
      for (std::size_t k = 0; k < K; ++k) {
        bool any = false;
        for (const Target& t : targets) any |= s.values[t.array][static_cast<std::size_t>(slots[k])] != 0;
        live[weighted] = k;
        weighted += any ? 1 : 0;
      }
      std::array<std::array<Real, m>, nc> pg{};
      for (std::size_t e = 0; e < weighted; ++e) {
        const std::size_t k = live[e];
        const auto p = monomials_at<M, Degree>(q, k);
        for (std::size_t c = 0; c < comps; ++c) {
          const Real gk = s.values[targets[c].array][static_cast<std::size_t>(slots[k])];
          for (std::size_t a = 0; a < m; ++a) pg[c][a] += p[a] * gk;
        }
      }
      Columns R = Columns::Zero();
      for (std::size_t c = 0; c < comps; ++c) {
        const Target& t = targets[c];
        for (std::size_t a = 0; a < m; ++a) R(static_cast<int>(a), static_cast<int>(c)) = -pg[c][a];
        R(t.monomial, static_cast<int>(c)) += t.order == 1 ? t.value / h : t.value / (h * h);
      }
      Columns Y;
      if (!equilibrated_spd_solve<M, C>(A, R, static_cast<Eigen::Index>(comps), Y, max_condition)) {
        kept_here.push_back(i);
        continue;
      }
      // δ_k = W_k p_k · y per component, every component in one pass over the neighbours (past
      // `comps`, y is zero and its products go unused: C is the callers' largest count).
      std::array<std::array<Real, m>, nc> y{};
      for (std::size_t c = 0; c < comps; ++c)
        for (std::size_t a = 0; a < m; ++a) y[c][a] = Y(static_cast<int>(a), static_cast<int>(c));
      // (Written as folds over constant indices: with loops over the components and monomials
      // inside, the compiler did not vectorise the loop over the neighbours.)
      for (std::size_t k = 0; k < K; ++k) {
        const auto p = monomials_at<M, Degree>(q, k);
        const Real wk = weight[k];
        [&]<std::size_t... Cs>(std::index_sequence<Cs...>) VRSPH_ALWAYS_INLINE {
          ((work[Cs * stride + k] = wk * fixed_dot(y[Cs], p)), ...);
        }(std::make_index_sequence<nc>{});
      }
      const auto diag = static_cast<std::size_t>(s.diag[si]);
      for (std::size_t c = 0; c < comps; ++c) {
        std::vector<Real>& g = s.values[targets[c].array];
        const Real* delta = work.data() + c * stride;
        Real added = 0;
        for (std::size_t k = 0; k < K; ++k) {
          g[static_cast<std::size_t>(slots[k])] += delta[k];
          added += delta[k];
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

