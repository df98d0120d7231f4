// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>
#include "../../core/compiler_hints.hpp"

// Every particle solves one NNLS, so the solver is compiled twice on x86-64 with GCC: for
// x86-64-v3 (AVX2 + FMA: four doubles per instruction, fused multiply-add) and for the
// baseline, and the loader picks the clone the CPU runs (an ifunc, resolved once).
// Measured with `vrsph_bench --benchmark_filter=Nnls`: see docs/performance.md. The clones:
// VRSPH_AVX2_CLONES (core/compiler_hints.hpp).
// The steps are lambdas forced inline: a lambda the compiler leaves out of line is a
// separate function without the clone's target, and runs the baseline code.

namespace vrsph {

namespace {
constexpr Real eps = std::numeric_limits<Real>::epsilon();
// Gram-Schmidt's update of an entering column in one blocked pass from this many rows on
// (the 35-row 3D compact systems gain; the 9-row point systems were 8 % slower a solve with it,
// the pass's temporary costing more than the short chains it removes).
constexpr std::size_t kBlockedUpdateRows = 12;

// Tolerances. The multiplier test uses METHODS §3.0's tol = 10 eps ||A||_1 max(m, n)
// (w = A^T r has the units of A b). lsqnonneg also drops variables with |x_j| < tol, but
// x has the units of b / A: for VRSPH ||A||_1 ~ h^-3 while the volumes are ~ dx^d, and at
// n = 1000 that test discarded genuine volumes and made the textbook algorithm cycle.
// Solving the equivalent problem (A / ||A||_1) x' = b with x' = ||A||_1 x and one
// tolerance 10 eps max(m, n) gives the scale-consistent x threshold tol / ||A||_1^2.
struct Tolerances {
  Real w, x;
};
Tolerances tolerances(Real a_norm1, int m, int n, Real user) {
  const Real tw = user >= 0 ? user : 10 * eps * a_norm1 * std::max(m, n);
  const Real scale = a_norm1 > 0 ? a_norm1 : 1;
  return {tw, tw / (scale * scale)};
}

// Four doubles as one value: GCC and Clang map it to one AVX register in the x86-64-v3
// clone and to two SSE registers in the baseline (the same loops written over scalars were
// left scalar by the vectoriser: the gradient alone was ~40% of a solve's instructions).
// memcpy: the columns are not 32-byte aligned. The helpers are macros-in-spirit (always
// inline, so no vector value crosses a call and the ABI of the baseline is untouched).
typedef Real Real4 __attribute__((vector_size(4 * sizeof(Real))));

// y[0:len] -= c x[0:len]
VRSPH_ALWAYS_INLINE inline void sub_scaled(Real* __restrict y, const Real* __restrict x, Real c, std::size_t len) {
  std::size_t i = 0;
  for (; i + 4 <= len; i += 4) {
    Real4 a, b;
    std::memcpy(&a, y + i, sizeof a);
    std::memcpy(&b, x + i, sizeof b);
    a -= c * b;
    std::memcpy(y + i, &a, sizeof a);
  }
  for (; i < len; ++i) y[i] -= c * x[i];
}

// x[0:len] . y[0:len]
VRSPH_ALWAYS_INLINE inline Real dot(const Real* __restrict x, const Real* __restrict y, std::size_t len) {
  Real4 acc = {0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 4 <= len; i += 4) {
    Real4 a, b;
    std::memcpy(&a, x + i, sizeof a);
    std::memcpy(&b, y + i, sizeof b);
    acc += a * b;
  }
  Real sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  for (; i < len; ++i) sum += x[i] * y[i];
  return sum;
}

// Rows [i, i + 4 B) of combine_columns below: B blocks of four rows, each accumulated in its own
// register over the columns (also A^T r: w[j:j+4B] = sum_i r_i At[i, j:j+4B], with At's rows as
// the columns). The B accumulators are independent chains, so the adds of one
// column overlap instead of each waiting out the previous add's latency (one block at a time
// ran at one vector add per latency period: a third of a 3D solve).
template <std::size_t B>
VRSPH_ALWAYS_INLINE inline void combine_blocks(Real* __restrict out, const Real* __restrict init, Real scale,
                                               const Real* __restrict cols, std::size_t stride,
                                               const Real* __restrict c, int cnt, std::size_t i) {
  Real4 acc[B];
#pragma GCC unroll 8
  for (std::size_t q = 0; q < B; ++q) acc[q] = Real4{0, 0, 0, 0};
  for (int j = 0; j < cnt; ++j) {
    const Real cj = c[j];
    const Real* col = cols + static_cast<std::size_t>(j) * stride + i;
#pragma GCC unroll 8
    for (std::size_t q = 0; q < B; ++q) {
      Real4 v;
      std::memcpy(&v, col + 4 * q, sizeof v);
      acc[q] += cj * v;
    }
  }
#pragma GCC unroll 8
  for (std::size_t q = 0; q < B; ++q) {
    acc[q] *= scale;
    if (init) {
      Real4 base;
      std::memcpy(&base, init + i + 4 * q, sizeof base);
      acc[q] += base;
    }
    std::memcpy(out + i + 4 * q, &acc[q], sizeof acc[q]);
  }
}

// Rows [i, i + T), T < 4, of combine_columns: their sums side by side (independent chains).
template <std::size_t T>
VRSPH_ALWAYS_INLINE inline void combine_tail(Real* __restrict out, const Real* __restrict init, Real scale,
                                             const Real* __restrict cols, std::size_t stride,
                                             const Real* __restrict c, int cnt, std::size_t i) {
  Real acc[T] = {};
  for (int j = 0; j < cnt; ++j) {
    const Real* col = cols + static_cast<std::size_t>(j) * stride + i;
#pragma GCC unroll 3
    for (std::size_t t = 0; t < T; ++t) acc[t] += c[j] * col[t];
  }
#pragma GCC unroll 3
  for (std::size_t t = 0; t < T; ++t) out[i + t] = (init ? init[i + t] : 0) + scale * acc[t];
}

// out[0:len] = init[0:len] + scale * sum_{j<cnt} c[j] cols[j*stride + 0:len] (init null:
// zero). Blocks of four rows accumulated in registers over the columns (updating out in
// memory column by column made every column wait for the previous one's store), up to eight
// blocks side by side. Each entry's sum runs over the columns in the same order whatever the
// blocking, so the result does not depend on it.
VRSPH_ALWAYS_INLINE inline void combine_columns(Real* __restrict out, const Real* __restrict init, Real scale,
                                                const Real* __restrict cols, std::size_t stride,
                                                const Real* __restrict c, int cnt, std::size_t len) {
  const std::size_t blocks = len / 4 * 4;
  std::size_t i = 0;
  for (; i + 32 <= blocks; i += 32) combine_blocks<8>(out, init, scale, cols, stride, c, cnt, i);
  if (i + 16 <= blocks) {
    combine_blocks<4>(out, init, scale, cols, stride, c, cnt, i);
    i += 16;
  }
  if (i + 8 <= blocks) {
    combine_blocks<2>(out, init, scale, cols, stride, c, cnt, i);
    i += 8;
  }
  if (i < blocks) combine_blocks<1>(out, init, scale, cols, stride, c, cnt, i);
  switch (len - blocks) {  // the last len % 4 rows
    case 1: return combine_tail<1>(out, init, scale, cols, stride, c, cnt, blocks);
    case 2: return combine_tail<2>(out, init, scale, cols, stride, c, cnt, blocks);
    case 3: return combine_tail<3>(out, init, scale, cols, stride, c, cnt, blocks);
    default: return;
  }
}

// c[l] = Q_l . v for the k columns Q_l = Q + l stride (len entries), four columns side by side
// (independent accumulators); each sum runs as dot()'s does.
VRSPH_ALWAYS_INLINE inline void project(Real* __restrict c, const Real* __restrict Q, std::size_t stride,
                                        const Real* __restrict v, int k, std::size_t len) {
  int l = 0;
  for (; l + 4 <= k; l += 4) {
    const Real* q = Q + static_cast<std::size_t>(l) * stride;
    Real4 acc[4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
    std::size_t i = 0;
    for (; i + 4 <= len; i += 4) {
      Real4 x;
      std::memcpy(&x, v + i, sizeof x);
#pragma GCC unroll 4
      for (int t = 0; t < 4; ++t) {
        Real4 a;
        std::memcpy(&a, q + static_cast<std::size_t>(t) * stride + i, sizeof a);
        acc[t] += a * x;
      }
    }
#pragma GCC unroll 4
    for (int t = 0; t < 4; ++t) {
      Real sum = (acc[t][0] + acc[t][1]) + (acc[t][2] + acc[t][3]);
      for (std::size_t r = i; r < len; ++r) sum += q[static_cast<std::size_t>(t) * stride + r] * v[r];
      c[l + t] = sum;
    }
  }
  for (; l < k; ++l) c[l] = dot(Q + static_cast<std::size_t>(l) * stride, v, len);
}

// First index of the largest w_j (with a tie width: the first within tie |best| of it) if
// that exceeds tol, else -1. Two passes: the maximum with
// four independent partial maxima (vectorisable; the running arg-max was one dependent
// compare per column, ~400 cycles per 3D iteration), then the first index holding it.
inline int entering_column(const Real* w, int n, Real tol, Real tie) {
  Real part[4] = {tol, tol, tol, tol};
  int j = 0;
  for (; j + 4 <= n; j += 4)
    for (int q = 0; q < 4; ++q) part[q] = w[j + q] > part[q] ? w[j + q] : part[q];
  for (; j < n; ++j) part[0] = w[j] > part[0] ? w[j] : part[0];
  const Real best = std::max(std::max(part[0], part[1]), std::max(part[2], part[3]));
  if (!(best > tol)) return -1;
  const Real threshold = tie > 0 ? best - tie * best : best;
  for (j = 0; j < n; ++j)
    if (w[j] >= threshold && w[j] > tol) return j;
  return -1;
}

// Givens rotation (c, s) with [c s; -s c] [a; b] = [r; 0].
inline void givens(Real a, Real b, Real& c, Real& s) {
  if (b == 0) {
    c = 1;
    s = 0;
    return;
  }
  // Plain sqrt: std::hypot's overflow guard cost 16% of the solve, and the entries of
  // VRSPH's moment systems are far from the overflow range.
  const Real r = std::sqrt(a * a + b * b);
  c = a / r;
  s = b / r;
}

// FixedM > 0: the size known at compile time (the loops unroll; a third of the fast path's time).
// Every loop unrolled up to 10 trips: the 9 x 9 systems' elimination becomes straight-line
// code, 1.3 times faster (225 -> 168 ns a solve, x86-64-v3, the same bits); 12 x 12 1.2 times,
// 19 x 19 within 5 %. GCC only: clang cannot unroll the elimination's outer loop (it returns
// early) and warns (-Wpass-failed); its builds are the sanitizer and fuzz ones (VRSPH_UNROLL_SMALL).
template <int FixedM>
VRSPH_AVX2_CLONES bool solve_square_impl(Real* S, int m, Real* z, Real xtol) {
  const auto M = static_cast<std::size_t>(FixedM > 0 ? FixedM : m);
  Real scale = 0;
  VRSPH_UNROLL_SMALL
  for (std::size_t e = 0; e < M * M; ++e) scale = std::max(scale, std::abs(S[e]));
  VRSPH_UNROLL_SMALL
  for (std::size_t c = 0; c < M; ++c) {  // LU with partial pivoting, applied to z as it goes
    std::size_t piv = c;
    VRSPH_UNROLL_SMALL
    for (std::size_t r = c + 1; r < M; ++r)
      if (std::abs(S[c * M + r]) > std::abs(S[c * M + piv])) piv = r;
    if (!(std::abs(S[c * M + piv]) > 1e3 * eps * scale * static_cast<Real>(M))) return false;  // (nearly) singular
    if (piv != c) {
      VRSPH_UNROLL_SMALL
      for (std::size_t j = 0; j < M; ++j) std::swap(S[j * M + c], S[j * M + piv]);
      std::swap(z[c], z[piv]);
    }
    // The multipliers into column c, then each later column updated along its contiguous rows
    // (the row-by-row form ran across columns with stride M and did not vectorise).
    const Real inv = 1 / S[c * M + c];
    Real* lc = S + c * M;
    VRSPH_UNROLL_SMALL
    for (std::size_t r = c + 1; r < M; ++r) {
      lc[r] *= inv;
      z[r] -= lc[r] * z[c];
    }
    VRSPH_UNROLL_SMALL
    for (std::size_t j = c + 1; j < M; ++j) {
      Real* sj = S + j * M;
      const Real scj = sj[c];
      VRSPH_UNROLL_SMALL
      for (std::size_t r = c + 1; r < M; ++r) sj[r] -= lc[r] * scj;
    }
  }
  // Back substitution column by column: z[c] is final when its column is reached, and its
  // updates of the rows above are independent. (Row by row, each unknown's sum began with the
  // one just found and waited for it: a chain of dependent subtractions per unknown.)
  VRSPH_UNROLL_SMALL
  for (std::size_t back = 0; back < M; ++back) {
    const std::size_t c = M - 1 - back;
    z[c] /= S[c * M + c];
    if (!(z[c] > xtol)) return false;
    const Real* sc = S + c * M;
    VRSPH_UNROLL_SMALL
    for (std::size_t r = 0; r < c; ++r) z[r] -= sc[r] * z[c];
  }
  return true;
}
}  // namespace

bool solve_square_positive(Real* S, int m, Real* z, Real xtol) {
  switch (m) {
    case 3: return solve_square_impl<3>(S, m, z, xtol);
    case 7: return solve_square_impl<7>(S, m, z, xtol);
    case 9: return solve_square_impl<9>(S, m, z, xtol);
    case 12: return solve_square_impl<12>(S, m, z, xtol);
    case 16: return solve_square_impl<16>(S, m, z, xtol);
    case 19: return solve_square_impl<19>(S, m, z, xtol);
    default: return solve_square_impl<0>(S, m, z, xtol);
  }
}

Real nnls_value_tolerance(Real a_norm1, int m, int n) { return tolerances(a_norm1, m, n, -1).x; }

NnlsSolver::NnlsSolver(int max_rows, int max_cols) { reserve(max_rows, max_cols); }

void NnlsSolver::reserve(int m, int n) {
  if (m <= cap_m_ && n <= cap_n_) return;
  cap_m_ = std::max(m, cap_m_);
  cap_n_ = std::max(n, cap_n_);
  const auto M = static_cast<std::size_t>(cap_m_), N = static_cast<std::size_t>(cap_n_);
  Q_.resize(M * M);
  R_.resize(M * M);
  qtb_.resize(M);
  z_.resize(M);
  xp_.resize(M);
  Rinv_.resize(M * M);
  r_.resize(M);
  w_.resize(N);
  at_.resize(M * N);
  gs_.resize(M);
  proj_.resize(M);
  passive_.resize(M);
  in_passive_.resize(N);
}

// Kept whole on purpose (about 250 lines, the one function of src/ above 120): the
// Lawson-Hanson iteration's inner and outer loops share the QR factor, the passive set and the
// workspaces, and the compiler specialises the whole loop nest on FixedRows; split into
// functions the state would travel through arguments on the hottest path of the library.
template <int FixedRows>
VRSPH_AVX2_CLONES NnlsResult NnlsSolver::solve_impl(const Real* A, int m_runtime, int n, const Real* b, Real* x,
                                                     const NnlsOptions& options, MatrixOrder order,
                                                     std::span<const int> initial_passive) {
  // With FixedRows > 0 the row count is a compile-time constant: the short loops over
  // rows unroll and vectorise (the row counts VRSPH uses are instantiated below).
  const int m = FixedRows > 0 ? FixedRows : m_runtime;
  const auto M = static_cast<std::size_t>(m);
  const auto N = static_cast<std::size_t>(n);
  Real* Q = Q_.data();  // column-major m x m; A_P = Q R
  Real* R = R_.data();  // column-major m x (k <= m), upper triangular
  Real* qtb = qtb_.data();
  const int max_it = options.max_iterations >= 0 ? options.max_iterations : 3 * std::max(n, 1);

  std::fill(x, x + n, 0.0);
  std::fill(in_passive_.begin(), in_passive_.begin() + n, 0);
  // The solver works on A row-major (A^T's columns contiguous): w = A^T r then runs over
  // contiguous rows of n entries (vectorises; column-major dot products of length m = 9 did
  // not). Column-major input is transposed here; VRSPH builds its systems row-major and
  // skips the copy. ||A||_1 (max column sum) comes from the same pass.
  const Real* At = A;
  Real a_norm1 = 0;
  if (order == MatrixOrder::ColumnMajor) {
    Real* copy = at_.data();
    for (std::size_t j = 0; j < N; ++j) {
      const Real* a = A + j * M;
      Real colsum = 0;
      for (std::size_t i = 0; i < M; ++i) {
        copy[i * N + j] = a[i];
        colsum += std::abs(a[i]);
      }
      a_norm1 = std::max(a_norm1, colsum);
    }
    At = copy;
  } else {
    Real* colsum = w_.data();
    std::fill(colsum, colsum + n, 0.0);
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = 0; j < N; ++j) colsum[j] += std::abs(At[i * N + j]);
    for (std::size_t j = 0; j < N; ++j) a_norm1 = std::max(a_norm1, colsum[j]);
  }
  // Column j of A gathered into out (m entries).
  auto gather_column = [&](int j, Real* out) VRSPH_ALWAYS_INLINE {
    for (std::size_t i = 0; i < M; ++i) out[i] = At[i * N + static_cast<std::size_t>(j)];
  };
  const Tolerances tols = tolerances(a_norm1, m, n, options.tolerance);
  const Real tol = tols.w, xtol = tols.x;
  int k = 0;  // passive count
  NnlsResult res;

  // R[0:k,0:k] z = qtb[0:k] through R^-1, kept column by column beside R (Rinv_: column-major,
  // zeros below the diagonal): z = R^-1 qtb is then k independent multiply-adds per block of
  // four rows. Back-substitution chained k dependent steps through memory (~15% of a 2D solve).
  Real* Rinv = Rinv_.data();
  auto back_substitute = [&]() VRSPH_ALWAYS_INLINE {
    combine_columns(z_.data(), nullptr, 1, Rinv, M, qtb, k, static_cast<std::size_t>(k));
  };
  // Column j of R^-1 from its columns 0..j-1: R^-1[:, j] = -R^-1[:, 0:j] R[0:j, j] / R_jj with
  // 1 / R_jj on the diagonal (the rows below stay zero).
  auto invert_column = [&](int j) VRSPH_ALWAYS_INLINE {
    const std::size_t jj = static_cast<std::size_t>(j);
    const Real* Rj = R + jj * M;
    const Real inv = 1 / Rj[jj];
    Real* out = Rinv + jj * M;
    combine_columns(out, nullptr, -inv, Rinv, M, Rj, j, jj);
    out[jj] = inv;
    for (std::size_t i = jj + 1; i < M; ++i) out[i] = 0;
  };
  // Apply the rotation (c, s) to rows (p, q) of Q^T, i.e. columns p, q of Q, and to qtb.
  auto rotate_q = [&](int p, int q, Real c, Real s) VRSPH_ALWAYS_INLINE {
    Real* Qp = Q + static_cast<std::size_t>(p) * M;
    Real* Qq = Q + static_cast<std::size_t>(q) * M;
    for (std::size_t i = 0; i < M; ++i) {
      const Real a = Qp[i], bq = Qq[i];
      Qp[i] = c * a + s * bq;
      Qq[i] = -s * a + c * bq;
    }
    const Real a = qtb[p], bq = qtb[q];
    qtb[p] = c * a + s * bq;
    qtb[q] = -s * a + c * bq;
  };
  // w = A^T r with r = b - Q1 (Q1^T b), Q1 the k orthonormal columns spanning A_P. Columns
  // in blocks with the partial sums in registers (one pass over A^T instead of m
  // read-modify-write passes over w). The residual norm is not needed here: the result
  // reports the true residual of the returned x, computed once at the end.
  auto gradient = [&]() VRSPH_ALWAYS_INLINE {
    combine_columns(r_.data(), b, -1, Q, M, qtb, k, M);  // r = b - Q1 (Q1^T b)
    // w = A^T r: combine_columns over A^T's rows (eight blocks of four columns side by side,
    // each a chain of m dependent adds: one or two chains waited on each add's latency).
    Real* w = w_.data();
    combine_columns(w, nullptr, 1, At, N, r_.data(), m, N);
    for (int p = 0; p < k; ++p) w[passive_[static_cast<std::size_t>(p)]] = -std::numeric_limits<Real>::infinity();  // never re-enters directly
  };
  // Appends column t as passive position k: classical Gram–Schmidt against the k passive
  // basis columns (the k dot products are independent, unlike modified GS's chain), with a
  // second pass only when the first cancelled more than half the norm (DGKS criterion;
  // "twice is enough"). Returns false (factorisation unchanged) if t is numerically
  // dependent on the passive set.
  auto add_column = [&](int t) VRSPH_ALWAYS_INLINE {
    // __restrict: the workspaces are distinct arrays and qk (column t of A, then its
    // orthogonalised copy) and Rk are read through no other pointer; without it every store
    // to qk forced the projections to be reloaded and the loops stayed scalar.
    Real* __restrict qk = Q + static_cast<std::size_t>(k) * M;
    gather_column(t, qk);
    Real* __restrict Rk = R + static_cast<std::size_t>(k) * M;
    const Real anorm2 = dot(qk, qk, M);
    for (int l = 0; l < k; ++l) Rk[l] = 0;
    Real vnorm2 = anorm2;  // ||qk||^2 after the last pass
    for (int pass = 0; pass < 2 && k > 0; ++pass) {
      Real* __restrict c = gs_.data();  // projections onto the passive basis
      project(c, Q, M, qk, k, M);
      if (M >= kBlockedUpdateRows) {
        // qk -= Q1 c in one pass over Q1 (blocked as combine_columns is; subtracting the k
        // projections one after the other made each pass over qk wait for the previous one).
        combine_columns(proj_.data(), qk, -1, Q, M, c, k, M);
        std::copy_n(proj_.data(), M, qk);
      } else {
        for (int l = 0; l < k; ++l) sub_scaled(qk, Q + static_cast<std::size_t>(l) * M, c[l], M);
      }
      for (int l = 0; l < k; ++l) Rk[l] += c[l];
      const Real before2 = vnorm2;
      vnorm2 = dot(qk, qk, M);
      if (vnorm2 > 0.5 * before2) break;  // ||q|| > ||a||/sqrt(2): orthogonal to working accuracy
    }
    const Real vnorm = std::sqrt(vnorm2);
    if (vnorm <= 100 * eps * std::sqrt(anorm2) * m) return false;
    const Real inv = 1 / vnorm;
    for (std::size_t i = 0; i < M; ++i) qk[i] *= inv;
    Rk[k] = vnorm;
    qtb[k] = dot(qk, b, M);  // (vectorised: the running sum beside the scaling was one chain of m adds)
    passive_[static_cast<std::size_t>(k)] = t;
    xp_[static_cast<std::size_t>(k)] = 0;  // t comes from the zero set
    in_passive_[static_cast<std::size_t>(t)] = 1;
    invert_column(k);
    ++k;
    return true;
  };
  // Removes passive position p; restores triangularity with Givens rotations.
  auto remove_position = [&](int p) VRSPH_ALWAYS_INLINE {
    in_passive_[static_cast<std::size_t>(passive_[static_cast<std::size_t>(p)])] = 0;
    for (int j = p; j < k - 1; ++j) {
      std::copy(R + static_cast<std::size_t>(j + 1) * M, R + static_cast<std::size_t>(j + 1) * M + M, R + static_cast<std::size_t>(j) * M);
      passive_[static_cast<std::size_t>(j)] = passive_[static_cast<std::size_t>(j) + 1];
      xp_[static_cast<std::size_t>(j)] = xp_[static_cast<std::size_t>(j) + 1];
    }
    --k;
    for (int j = p; j < k; ++j) {  // R is upper Hessenberg in columns p..k-1
      Real c, s;
      const std::size_t jj = static_cast<std::size_t>(j);
      givens(R[jj * M + jj], R[jj * M + jj + 1], c, s);
      if (s == 0) continue;
      for (int l = j; l < k; ++l) {
        Real* Rl = R + static_cast<std::size_t>(l) * M;
        const Real a = Rl[jj], bb = Rl[jj + 1];
        Rl[jj] = c * a + s * bb;
        Rl[jj + 1] = -s * a + c * bb;
      }
      rotate_q(j, j + 1, c, s);
      // R^-1 follows without being recomputed: the rotations act on R's rows j, j + 1, so on
      // R^-1's columns j, j + 1 (rows 0..j+1; the rest are zero).
      Real* Ij = Rinv + jj * M;
      Real* Ij1 = Ij + M;
      for (std::size_t i = 0; i <= jj + 1; ++i) {
        const Real a = Ij[i], bq = Ij1[i];
        Ij[i] = c * a + s * bq;
        Ij1[i] = -s * a + c * bq;
      }
    }
    // The rotated R (column p gone) times the rotated R^-1 is the identity with row p of the
    // latter deleted and its last column dropped (with column p moved last, the rotated old R is
    // upper triangular with the new R as its leading block). So R^-1's rows below p move up one
    // in columns p..k-1, and the entry under each diagonal (zero in exact arithmetic) is zeroed.
    // O(k^2); recomputing those columns from R was O(k^3), a sixth of a 3D solve.
    for (int j = p; j < k; ++j) {
      Real* col = Rinv + static_cast<std::size_t>(j) * M;
      for (int i = p; i <= j; ++i) col[i] = col[i + 1];
      col[j + 1] = 0;
    }
  };

  // One Lawson–Hanson step with entering column t from a feasible x (x_P = argmin on P,
  // x_P > 0): t joins P if it is independent of P and its least-squares value is positive
  // (the LH safeguard), then the inner loop steps back towards feasibility, dropping the
  // variables that reach zero. Returns false if t was not admitted (nothing changed).
  auto enter = [&](int t) VRSPH_ALWAYS_INLINE {
    if (!add_column(t)) return false;
    back_substitute();
    if (z_[static_cast<std::size_t>(k) - 1] <= 0) {
      remove_position(k - 1);
      return false;
    }
    for (;;) {
      int neg = -1;
      Real alpha = std::numeric_limits<Real>::infinity();
      for (int p = 0; p < k; ++p)
        if (z_[static_cast<std::size_t>(p)] <= 0) {
          const Real xv = xp_[static_cast<std::size_t>(p)], den = xv - z_[static_cast<std::size_t>(p)];
          const Real a = den > 0 ? xv / den : 0;
          if (a < alpha) {
            alpha = a;
            neg = p;
          }
        }
      if (neg < 0) break;
      if (++res.iterations > max_it) {
        res.status = NnlsStatus::IterationLimit;
        break;
      }
      for (int p = 0; p < k; ++p) xp_[static_cast<std::size_t>(p)] += alpha * (z_[static_cast<std::size_t>(p)] - xp_[static_cast<std::size_t>(p)]);
      xp_[static_cast<std::size_t>(neg)] = 0;
      for (int p = k - 1; p >= 0; --p)
        if (std::abs(xp_[static_cast<std::size_t>(p)]) < xtol) remove_position(p);
      back_substitute();
    }
    if (res.status == NnlsStatus::IterationLimit) return true;  // keep the last feasible x
    for (int p = 0; p < k; ++p) xp_[static_cast<std::size_t>(p)] = z_[static_cast<std::size_t>(p)];
    return true;
  };

  // Warm start: the guessed columns enter, then those with non-positive least-squares values
  // leave (all at once, and again until none is left), which ends at a feasible x_P > 0 that
  // is the least-squares solution on P: the invariant the iteration below starts from (the
  // cold start's P is empty). No step-back is possible here: x is 0 outside P. (A guess of m
  // columns that is still optimal is cheaper still by solve_square_positive, which VRSPH tries
  // first: VolumeRows::square_row.)
  if (!initial_passive.empty()) {
    for (const int t : initial_passive)
      if (k < m && t >= 0 && t < n && !in_passive_[static_cast<std::size_t>(t)]) add_column(t);
    for (;;) {
      back_substitute();
      bool dropped = false;
      for (int p = k - 1; p >= 0; --p)
        if (!(z_[static_cast<std::size_t>(p)] > xtol)) {
          remove_position(p);
          dropped = true;
        }
      if (!dropped) break;
    }
    for (int p = 0; p < k; ++p) xp_[static_cast<std::size_t>(p)] = z_[static_cast<std::size_t>(p)];
    res.warm_kept = k;
  }
  if (k < m) gradient();
  while (k < m && res.status == NnlsStatus::Converged) {
    // Entering column: largest multiplier among the zero set (first index on ties; passive
    // and rejected columns hold w = -inf).
    const int t = entering_column(w_.data(), n, tol, options.tie_tolerance);
    if (t < 0) break;
    if (++res.iterations > max_it) {
      res.status = NnlsStatus::IterationLimit;
      break;
    }
    if (!enter(t)) {
      w_[static_cast<std::size_t>(t)] = -std::numeric_limits<Real>::infinity();  // rejected until x changes
      continue;
    }
    if (res.status == NnlsStatus::IterationLimit) break;
    gradient();
  }
  for (int p = 0; p < k; ++p) x[passive_[static_cast<std::size_t>(p)]] = std::max(xp_[static_cast<std::size_t>(p)], 0.0);
  res.passive = k;
  // Report the true residual of the returned x.
  for (std::size_t i = 0; i < M; ++i) r_[i] = b[i];
  for (int p = 0; p < k; ++p) {
    const int j = passive_[static_cast<std::size_t>(p)];
    gather_column(j, gs_.data());
    sub_scaled(r_.data(), gs_.data(), x[j], M);
  }
  Real r2 = 0;
  for (std::size_t i = 0; i < M; ++i) r2 += r_[i] * r_[i];
  res.residual = std::sqrt(r2);
  return res;
}

NnlsResult NnlsSolver::solve(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options,
                             MatrixOrder order) {
  return solve(A, m, n, b, x, options, order, {});
}

NnlsResult NnlsSolver::solve(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options,
                             MatrixOrder order, std::span<const int> init) {
  check<InputError>(m >= 1 && n >= 0, "NNLS: invalid problem size ", m, " x ", n);
  reserve(m, n);
  switch (m) {
    case 2: return solve_impl<2>(A, m, n, b, x, options, order, init);
    case 3: return solve_impl<3>(A, m, n, b, x, options, order, init);
    case 7: return solve_impl<7>(A, m, n, b, x, options, order, init);
    case 9: return solve_impl<9>(A, m, n, b, x, options, order, init);
    case 10: return solve_impl<10>(A, m, n, b, x, options, order, init);
    case 12: return solve_impl<12>(A, m, n, b, x, options, order, init);
    case 15: return solve_impl<15>(A, m, n, b, x, options, order, init);  // 2D compact rows (rhs=compact)
    case 16: return solve_impl<16>(A, m, n, b, x, options, order, init);
    case 19: return solve_impl<19>(A, m, n, b, x, options, order, init);
    case 20: return solve_impl<20>(A, m, n, b, x, options, order, init);  // 3D compact rows of degree 3
    case 27: return solve_impl<27>(A, m, n, b, x, options, order, init);
    case 30: return solve_impl<30>(A, m, n, b, x, options, order, init);
    case 35: return solve_impl<35>(A, m, n, b, x, options, order, init);  // 3D compact rows (degree 4)
    default: return solve_impl<0>(A, m, n, b, x, options, order, init);
  }
}

NnlsResult nnls_reference(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& x, const NnlsOptions& o) {
  const Eigen::Index m = A.rows(), n = A.cols();
  check<InputError>(b.size() == m, "NNLS: b has ", b.size(), " entries for ", m, " rows");
  const Tolerances tols = tolerances(n > 0 ? A.cwiseAbs().colwise().sum().maxCoeff() : 0.0, static_cast<int>(m),
                                     static_cast<int>(n), o.tolerance);
  const Real tol = tols.w;
  const int max_it = o.max_iterations >= 0 ? o.max_iterations : 3 * static_cast<int>(std::max<Eigen::Index>(n, 1));
  x = Eigen::VectorXd::Zero(n);
  std::vector<bool> P(static_cast<std::size_t>(n), false);
  NnlsResult res;
  auto solve_passive = [&] {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index j = 0; j < n; ++j)
      if (P[static_cast<std::size_t>(j)]) idx.push_back(j);
    if (idx.empty()) return Eigen::VectorXd::Zero(n).eval();
    Eigen::MatrixXd Ap(m, static_cast<Eigen::Index>(idx.size()));
    for (std::size_t c = 0; c < idx.size(); ++c) Ap.col(static_cast<Eigen::Index>(c)) = A.col(idx[c]);
    const Eigen::VectorXd zp = Ap.colPivHouseholderQr().solve(b);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    for (std::size_t c = 0; c < idx.size(); ++c) z[idx[c]] = zp[static_cast<Eigen::Index>(c)];
    return z.eval();
  };
  Eigen::VectorXd w = A.transpose() * (b - A * x);
  for (;;) {
    Eigen::Index t = -1;
    Real best = tol;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!P[static_cast<std::size_t>(j)] && w[j] > best) {
        best = w[j];
        t = j;
      }
    if (t < 0) break;
    if (++res.iterations > max_it) {
      res.status = NnlsStatus::IterationLimit;
      break;
    }
    P[static_cast<std::size_t>(t)] = true;
    Eigen::VectorXd z = solve_passive();
    for (;;) {
      bool any = false;
      Real alpha = std::numeric_limits<Real>::infinity();
      for (Eigen::Index j = 0; j < n; ++j)
        if (P[static_cast<std::size_t>(j)] && z[j] <= 0) {
          any = true;
          alpha = std::min(alpha, x[j] - z[j] > 0 ? x[j] / (x[j] - z[j]) : 0.0);
        }
      if (!any) break;
      if (++res.iterations > max_it) {
        res.status = NnlsStatus::IterationLimit;
        break;
      }
      x += alpha * (z - x);
      for (Eigen::Index j = 0; j < n; ++j)
        if (P[static_cast<std::size_t>(j)] && std::abs(x[j]) < tols.x) P[static_cast<std::size_t>(j)] = false;
      z = solve_passive();
    }
    if (res.status == NnlsStatus::IterationLimit) break;
    x = z;
    w = A.transpose() * (b - A * x);
  }
  x = x.cwiseMax(0.0);
  res.passive = static_cast<int>(std::count(P.begin(), P.end(), true));
  res.residual = (A * x - b).norm();
  return res;
}

}  // namespace vrsph
