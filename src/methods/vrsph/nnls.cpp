#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>

namespace vrsph {

namespace {
constexpr Real eps = std::numeric_limits<Real>::epsilon();

Real norm1(const Real* A, int m, int n) {  // max column sum
  Real out = 0;
  for (int j = 0; j < n; ++j) {
    Real s = 0;
    for (int i = 0; i < m; ++i) s += std::abs(A[static_cast<std::size_t>(j) * static_cast<std::size_t>(m) + static_cast<std::size_t>(i)]);
    out = std::max(out, s);
  }
  return out;
}

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
}  // namespace

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
  rinv_.resize(M);
  r_.resize(M);
  w_.resize(N);
  at_.resize(M * N);
  gs_.resize(M);
  passive_.resize(M);
  in_passive_.resize(N);
}

template <int FixedRows>
NnlsResult NnlsSolver::solve_impl(const Real* A, int m_runtime, int n, const Real* b, Real* x, const NnlsOptions& options) {
  // With FixedRows > 0 the row count is a compile-time constant: the short loops over
  // rows unroll and vectorise (the row counts VRSPH uses are instantiated below).
  const int m = FixedRows > 0 ? FixedRows : m_runtime;
  const auto M = static_cast<std::size_t>(m);
  auto col = [&](int j) { return A + static_cast<std::size_t>(j) * M; };
  Real* Q = Q_.data();  // column-major m x m; A_P = Q R
  Real* R = R_.data();  // column-major m x (k <= m), upper triangular
  Real* qtb = qtb_.data();
  const Tolerances tols = tolerances(norm1(A, m, n), m, n, options.tolerance);
  const Real tol = tols.w, xtol = tols.x;
  const int max_it = options.max_iterations >= 0 ? options.max_iterations : 3 * std::max(n, 1);

  std::fill(x, x + n, 0.0);
  std::fill(in_passive_.begin(), in_passive_.begin() + n, 0);
  // Row-major copy of A: w = A^T r then runs over contiguous rows of n entries (vectorises;
  // the column-major dot products of length m = 9 did not): +6% throughput in 2D.
  const auto N = static_cast<std::size_t>(n);
  Real* At = at_.data();
  for (int j = 0; j < n; ++j) {
    const Real* a = col(j);
    for (std::size_t i = 0; i < M; ++i) At[i * N + static_cast<std::size_t>(j)] = a[i];
  }
  int k = 0;  // passive count
  NnlsResult res;

  // R[0:k,0:k] z = qtb[0:k]; rinv_ holds 1/R_ii (divisions were 8% of the solve).
  auto back_substitute = [&] {
    for (int i = k - 1; i >= 0; --i) {
      Real s = qtb[i];
      for (int j = i + 1; j < k; ++j) s -= R[static_cast<std::size_t>(j) * M + static_cast<std::size_t>(i)] * z_[static_cast<std::size_t>(j)];
      z_[static_cast<std::size_t>(i)] = s * rinv_[static_cast<std::size_t>(i)];
    }
  };
  // Apply the rotation (c, s) to rows (p, q) of Q^T, i.e. columns p, q of Q, and to qtb.
  auto rotate_q = [&](int p, int q, Real c, Real s) {
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
  // w = A^T r with r = b - Q1 (Q1^T b), Q1 the k orthonormal columns spanning A_P.
  auto gradient = [&] {
    for (std::size_t i = 0; i < M; ++i) r_[i] = b[i];
    for (int j = 0; j < k; ++j) {
      const Real t = qtb[j];
      const Real* Qj = Q + static_cast<std::size_t>(j) * M;
      for (std::size_t i = 0; i < M; ++i) r_[i] -= t * Qj[i];
    }
    Real res2 = 0;
    for (std::size_t i = 0; i < M; ++i) res2 += r_[i] * r_[i];
    Real* w = w_.data();
    std::fill(w, w + n, 0.0);
    for (std::size_t i = 0; i < M; ++i) {
      const Real ri = r_[i];
      const Real* row = At + i * N;
      for (std::size_t j = 0; j < N; ++j) w[j] += ri * row[j];
    }
    for (int p = 0; p < k; ++p) w[passive_[static_cast<std::size_t>(p)]] = -std::numeric_limits<Real>::infinity();  // never re-enters directly
    return std::sqrt(res2);
  };
  // Appends column t as passive position k: classical Gram–Schmidt against the k passive
  // basis columns (the k dot products are independent, unlike modified GS's chain), with a
  // second pass only when the first cancelled more than half the norm (DGKS criterion;
  // "twice is enough"). Returns false (factorisation unchanged) if t is numerically
  // dependent on the passive set.
  auto add_column = [&](int t) {
    const Real* a = col(t);
    Real* qk = Q + static_cast<std::size_t>(k) * M;
    Real* Rk = R + static_cast<std::size_t>(k) * M;
    Real anorm2 = 0;
    for (std::size_t i = 0; i < M; ++i) {
      qk[i] = a[i];
      anorm2 += a[i] * a[i];
    }
    for (int l = 0; l < k; ++l) Rk[l] = 0;
    Real before2 = anorm2;
    for (int pass = 0; pass < 2; ++pass) {
      Real* c = gs_.data();  // projections onto the passive basis
      for (int l = 0; l < k; ++l) {
        const Real* Ql = Q + static_cast<std::size_t>(l) * M;
        Real d = 0;
        for (std::size_t i = 0; i < M; ++i) d += Ql[i] * qk[i];
        c[l] = d;
      }
      for (int l = 0; l < k; ++l) {
        const Real* Ql = Q + static_cast<std::size_t>(l) * M;
        for (std::size_t i = 0; i < M; ++i) qk[i] -= c[l] * Ql[i];
        Rk[l] += c[l];
      }
      Real after2 = 0;
      for (std::size_t i = 0; i < M; ++i) after2 += qk[i] * qk[i];
      if (k == 0 || after2 > 0.5 * before2) break;  // ||q|| > ||a||/sqrt(2): orthogonal to working accuracy
      before2 = after2;
    }
    Real vnorm2 = 0;
    for (std::size_t i = 0; i < M; ++i) vnorm2 += qk[i] * qk[i];
    const Real vnorm = std::sqrt(vnorm2);
    if (vnorm <= 100 * eps * std::sqrt(anorm2) * m) return false;
    Real qb = 0;
    for (std::size_t i = 0; i < M; ++i) {
      qk[i] /= vnorm;
      qb += qk[i] * b[i];
    }
    Rk[k] = vnorm;
    rinv_[static_cast<std::size_t>(k)] = 1 / vnorm;
    qtb[k] = qb;
    passive_[static_cast<std::size_t>(k)] = t;
    xp_[static_cast<std::size_t>(k)] = 0;  // t comes from the zero set
    in_passive_[static_cast<std::size_t>(t)] = 1;
    ++k;
    return true;
  };
  // Removes passive position p; restores triangularity with Givens rotations.
  auto remove_position = [&](int p) {
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
    }
    for (int j = p; j < k; ++j) rinv_[static_cast<std::size_t>(j)] = 1 / R[static_cast<std::size_t>(j) * M + static_cast<std::size_t>(j)];
  };

  res.residual = gradient();
  while (k < m) {
    // Entering column: largest multiplier among the zero set (first index on ties).
    int t = -1;
    Real best = tol;
    for (int j = 0; j < n; ++j)  // passive and rejected columns hold w = -inf
      if (w_[static_cast<std::size_t>(j)] > best) {
        best = w_[static_cast<std::size_t>(j)];
        t = j;
      }
    if (t < 0) break;
    if (++res.iterations > max_it) {
      res.status = NnlsStatus::IterationLimit;
      break;
    }
    if (!add_column(t)) {
      w_[static_cast<std::size_t>(t)] = -std::numeric_limits<Real>::infinity();  // rejected until x changes
      continue;
    }
    back_substitute();
    if (z_[static_cast<std::size_t>(k) - 1] <= 0) {  // LH safeguard: t must enter with a positive value
      remove_position(k - 1);
      w_[static_cast<std::size_t>(t)] = -std::numeric_limits<Real>::infinity();
      continue;
    }
    // Inner loop: step back towards the feasible region while some z <= 0.
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
    if (res.status == NnlsStatus::IterationLimit) break;
    for (int p = 0; p < k; ++p) xp_[static_cast<std::size_t>(p)] = z_[static_cast<std::size_t>(p)];
    res.residual = gradient();
  }
  for (int p = 0; p < k; ++p) x[passive_[static_cast<std::size_t>(p)]] = std::max(xp_[static_cast<std::size_t>(p)], 0.0);
  res.passive = k;
  // Report the true residual of the returned x.
  Real r2 = 0;
  for (std::size_t i = 0; i < M; ++i) {
    Real s = -b[i];
    for (int p = 0; p < k; ++p) s += col(passive_[static_cast<std::size_t>(p)])[i] * x[passive_[static_cast<std::size_t>(p)]];
    r2 += s * s;
  }
  res.residual = std::sqrt(r2);
  return res;
}

NnlsResult NnlsSolver::solve(const Real* A, int m, int n, const Real* b, Real* x, const NnlsOptions& options) {
  check<InputError>(m >= 1 && n >= 0, "NNLS: invalid problem size ", m, " x ", n);
  reserve(m, n);
  switch (m) {
    case 2: return solve_impl<2>(A, m, n, b, x, options);
    case 3: return solve_impl<3>(A, m, n, b, x, options);
    case 7: return solve_impl<7>(A, m, n, b, x, options);
    case 9: return solve_impl<9>(A, m, n, b, x, options);
    case 10: return solve_impl<10>(A, m, n, b, x, options);
    case 12: return solve_impl<12>(A, m, n, b, x, options);
    case 16: return solve_impl<16>(A, m, n, b, x, options);
    case 19: return solve_impl<19>(A, m, n, b, x, options);
    case 27: return solve_impl<27>(A, m, n, b, x, options);
    case 30: return solve_impl<30>(A, m, n, b, x, options);
    default: return solve_impl<0>(A, m, n, b, x, options);
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
