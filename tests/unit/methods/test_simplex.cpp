// SPDX-License-Identifier: BSD-3-Clause
// DenseSimplex: the optimum of small linear programs against brute-force enumeration of their
// vertices, degenerate and rank-deficient systems of the compact rows' shape (b = e_m),
// infeasible and unbounded problems (with the bound on the residual an infeasible one proves),
// and a workspace that grows on demand.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>
#include <vrsph/methods/vrsph/nnls.hpp>
#include <vrsph/methods/vrsph/simplex.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

LpResult solve_lp(const RowMajor& A, const Eigen::VectorXd& b, const Eigen::VectorXd& c, Eigen::VectorXd& x) {
  DenseSimplex s(1, 1);  // deliberately small: the workspace must grow on demand
  x.resize(A.cols());
  return s.solve(A.data(), static_cast<int>(A.rows()), static_cast<int>(A.cols()), b.data(), c.data(), x.data());
}

// The least c^T x over the basic feasible solutions (every choice of m independent columns
// whose solution is >= 0): the LP's optimum when A has full row rank and the LP is bounded.
double best_vertex(const RowMajor& A, const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  const int m = static_cast<int>(A.rows()), n = static_cast<int>(A.cols());
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> pick(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) pick[static_cast<std::size_t>(k)] = k;
  for (;;) {
    Eigen::MatrixXd B(m, m);
    for (int k = 0; k < m; ++k) B.col(k) = A.col(pick[static_cast<std::size_t>(k)]);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
    if (lu.rank() == m) {
      const Eigen::VectorXd xb = lu.solve(b);
      if (xb.minCoeff() >= -1e-12) {
        double obj = 0;
        for (int k = 0; k < m; ++k) obj += c[pick[static_cast<std::size_t>(k)]] * xb[k];
        best = std::min(best, obj);
      }
    }
    int k = m - 1;  // next combination
    while (k >= 0 && pick[static_cast<std::size_t>(k)] == n - m + k) --k;
    if (k < 0) break;
    ++pick[static_cast<std::size_t>(k)];
    for (int l = k + 1; l < m; ++l) pick[static_cast<std::size_t>(l)] = pick[static_cast<std::size_t>(l) - 1] + 1;
  }
  return best;
}

// A random program min c^T x, A x = b, x >= 0 with c >= 0 (bounded): feasible by construction
// (b = A x0, x0 >= 0), or of the compact rows' shape (homogeneous rows and Σ x_j = 1 over the
// last n/2 columns: feasible when 0 is in the convex hull of those columns' other entries).
// The distributions are the caller's, so that a sequence of calls draws one stream.
struct Program {
  RowMajor A;
  Eigen::VectorXd b, c;
};
Program random_program(std::mt19937& rng, std::normal_distribution<double>& g, std::uniform_real_distribution<double>& u,
                       int m, int n, bool compact_shape) {
  Program p{RowMajor(m, n), Eigen::VectorXd(m), Eigen::VectorXd(n)};
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) p.A(i, j) = g(rng);
  if (!compact_shape) {
    Eigen::VectorXd x0(n);
    for (int j = 0; j < n; ++j) x0[j] = u(rng) < 0.5 ? 0.0 : u(rng);
    p.b = p.A * x0;
  } else {
    for (int j = 0; j < n; ++j) p.A(m - 1, j) = j >= n / 2 ? 1.0 : 0.0;
    p.b.setZero();
    p.b[m - 1] = 1;
  }
  for (int j = 0; j < n; ++j) p.c[j] = u(rng);
  return p;
}
}  // namespace

TEST(Simplex, TextbookProblem) {
  // min -3 x1 - 5 x2 s.t. x1 + s1 = 4, 2 x2 + s2 = 12, 3 x1 + 2 x2 + s3 = 18: x = (2, 6).
  RowMajor A(3, 5);
  A << 1, 0, 1, 0, 0,  //
      0, 2, 0, 1, 0,   //
      3, 2, 0, 0, 1;
  const Eigen::VectorXd b = (Eigen::VectorXd(3) << 4, 12, 18).finished();
  const Eigen::VectorXd c = (Eigen::VectorXd(5) << -3, -5, 0, 0, 0).finished();
  Eigen::VectorXd x;
  const LpResult r = solve_lp(A, b, c, x);
  ASSERT_EQ(r.status, LpStatus::Optimal);
  EXPECT_NEAR(x[0], 2, 1e-12);
  EXPECT_NEAR(x[1], 6, 1e-12);
  EXPECT_NEAR(r.objective, -36, 1e-12);
}

TEST(Simplex, AgreesWithTheBestVertexOfRandomProblems) {
  // Feasible by construction (b = A x0, x0 >= 0), c >= 0 (bounded), and half of them of the
  // compact rows' shape: b = e_m with a last row of ones over some columns.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 2 + trial % 4, n = m + 3 + trial % 5;
    // (Of the compact rows' shape, an infeasible one must be said so.)
    const auto [A, b, c] = random_program(rng, g, u, m, n, trial % 2 != 0);
    Eigen::VectorXd x;
    const LpResult r = solve_lp(A, b, c, x);
    const double best = best_vertex(A, b, c);
    if (std::isinf(best)) {
      EXPECT_EQ(r.status, LpStatus::Infeasible) << "trial " << trial;
      continue;
    }
    ASSERT_EQ(r.status, LpStatus::Optimal) << "trial " << trial;
    EXPECT_GE(x.minCoeff(), 0.0) << "trial " << trial;
    EXPECT_LT((A * x - b).norm(), 1e-10 * (1 + b.norm())) << "trial " << trial;
    EXPECT_NEAR(r.objective, best, 1e-10 * (1 + std::abs(best))) << "trial " << trial;
    EXPECT_NEAR(c.dot(x), r.objective, 1e-12 * (1 + std::abs(best))) << "trial " << trial;
  }
}

TEST(Simplex, RepeatedRowsAndZeroColumns) {
  // A rank-deficient A (row 2 = row 0) and a zero column: the repeated row keeps its
  // artificial variable at zero, the answer is still the optimum.
  RowMajor A(3, 5);
  A << 1, -1, 0, 2, 0,  //
      0, 1, -1, 0, 0,   //
      1, -1, 0, 2, 0;
  A.row(2) = A.row(0);
  const Eigen::VectorXd b = (Eigen::VectorXd(3) << 1, 0, 1).finished();
  const Eigen::VectorXd c = (Eigen::VectorXd(5) << 1, 1, 1, 1, 0).finished();
  Eigen::VectorXd x;
  const LpResult r = solve_lp(A, b, c, x);
  ASSERT_EQ(r.status, LpStatus::Optimal);
  EXPECT_LT((A * x - b).norm(), 1e-12);
  EXPECT_NEAR(r.objective, 0.5, 1e-12);  // x4 = 1/2
  EXPECT_EQ(x[4], 0.0);
}

TEST(Simplex, InfeasibleAndUnboundedProblemsAreSaid) {
  RowMajor A(1, 2);
  A << 1, 1;
  Eigen::VectorXd x;
  // x1 + x2 = -1 with x >= 0: the nearest is x = 0, at distance 1, and the certificate
  // y = -1 (A^T y = (-1, -1) <= 0, b^T y = 1) proves exactly that.
  const LpResult no = solve_lp(A, Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Ones(2), x);
  EXPECT_EQ(no.status, LpStatus::Infeasible);
  EXPECT_NEAR(no.residual_bound, 1.0, 1e-14);
  EXPECT_EQ(x.cwiseAbs().maxCoeff(), 0.0);
  // x1 - x2 = 0, min -x1: unbounded along x1 = x2.
  A << 1, -1;
  EXPECT_EQ(solve_lp(A, Eigen::VectorXd::Zero(1), (Eigen::VectorXd(2) << -1, 0).finished(), x).status,
            LpStatus::Unbounded);
  // The iteration limit is said too.
  RowMajor B(2, 4);
  B << 1, 2, 3, 4,  //
      1, 1, 1, 1;
  DenseSimplex s;
  Eigen::VectorXd y(4), bb = (Eigen::VectorXd(2) << 2.5, 1).finished(), cc = Eigen::VectorXd::Ones(4);
  LpOptions o;
  o.max_iterations = 0;
  EXPECT_EQ(s.solve(B.data(), 2, 4, bb.data(), cc.data(), y.data(), o).status, LpStatus::IterationLimit);
  EXPECT_THROW_MSG((void)s.solve(B.data(), 0, 4, bb.data(), cc.data(), y.data()), InputError, "invalid problem size");
}

TEST(Simplex, AnInfeasibleProgramBoundsTheResidualOfEveryNonNegativeX) {
  // Problems of the compact rows' shape (homogeneous rows, Σ x = 1 over half the columns) that
  // have no x >= 0: the bound phase 1's dual gives must lie below the least residual, which
  // the NNLS finds, and be positive (a certificate) on nearly all of them.
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  int infeasible = 0, certified = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int m = 3 + trial % 6, n = m + 2 + trial % 7;
    RowMajor A(m, n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) A(i, j) = g(rng) + (i == 0 ? 1.0 : 0.0);  // row 0 mostly positive: often infeasible
    for (int j = 0; j < n; ++j) A(m - 1, j) = j >= n / 2 ? 1.0 : 0.0;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(m), c = Eigen::VectorXd::Ones(n), x;
    b[m - 1] = 1;
    const LpResult r = solve_lp(A, b, c, x);
    if (r.status != LpStatus::Infeasible) continue;
    ++infeasible;
    NnlsSolver nnls(m, n);
    Eigen::VectorXd xn = Eigen::VectorXd::Zero(n);
    const NnlsResult least = nnls.solve(A.data(), m, n, b.data(), xn.data(), {}, MatrixOrder::RowMajor);
    ASSERT_EQ(least.status, NnlsStatus::Converged) << "trial " << trial;
    EXPECT_LE(r.residual_bound, (A * xn - b).norm() * (1 + 1e-10) + 1e-14) << "trial " << trial;
    EXPECT_GE(r.residual_bound, 0.0);
    certified += r.residual_bound > 0 ? 1 : 0;
  }
  EXPECT_GE(infeasible, 100);
  EXPECT_GE(certified, infeasible * 9 / 10);
}

TEST(Simplex, PhaseTwoFromAnNnlsVertexReachesTheSameOptimum) {
  // Feasible programs of both shapes: phase 2 started from the NNLS's answer (a vertex: its
  // positive columns independent) must end at phase 1 + 2's optimum, and phase 1 under a pivot
  // limit of 0 says so. A start whose columns make an infeasible basis is refused.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 3 + trial % 5, n = m + 4 + trial % 6;
    const auto [A, b, c] = random_program(rng, g, u, m, n, trial % 2 != 0);
    Eigen::VectorXd x;
    const LpResult full = solve_lp(A, b, c, x);
    if (full.status != LpStatus::Optimal) continue;
    NnlsSolver nnls(m, n);
    Eigen::VectorXd start = Eigen::VectorXd::Zero(n), y(n);
    ASSERT_EQ(nnls.solve(A.data(), m, n, b.data(), start.data(), {}, MatrixOrder::RowMajor).status, NnlsStatus::Converged);
    if ((A * start - b).norm() > 1e-12 * (1 + b.norm())) continue;  // the NNLS's own tolerance
    DenseSimplex s;
    const LpResult from = s.solve_from(A.data(), m, n, b.data(), c.data(), start.data(), y.data());
    ASSERT_EQ(from.status, LpStatus::Optimal) << "trial " << trial;
    EXPECT_GE(y.minCoeff(), 0.0);
    EXPECT_LT((A * y - b).norm(), 1e-10 * (1 + b.norm())) << "trial " << trial;
    EXPECT_NEAR(from.objective, full.objective, 1e-10 * (1 + std::abs(full.objective))) << "trial " << trial;
    ++compared;
    LpOptions o;
    o.phase1_iterations = 0;
    EXPECT_EQ(s.solve(A.data(), m, n, b.data(), c.data(), y.data(), o).status, LpStatus::IterationLimit);
  }
  EXPECT_GE(compared, 100);
  // x1 - x2 = 1 from the start (0, 1): the basis {x2} has x2 = -1.
  RowMajor A(1, 2);
  A << 1, -1;
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(1), c = Eigen::VectorXd::Ones(2), start = (Eigen::VectorXd(2) << 0, 1).finished();
  Eigen::VectorXd y(2);
  DenseSimplex s;
  EXPECT_EQ(s.solve_from(A.data(), 1, 2, b.data(), c.data(), start.data(), y.data()).status, LpStatus::Infeasible);
  const Eigen::VectorXd good = (Eigen::VectorXd(2) << 1, 0).finished();
  const LpResult r = s.solve_from(A.data(), 1, 2, b.data(), c.data(), good.data(), y.data());
  ASSERT_EQ(r.status, LpStatus::Optimal);
  EXPECT_NEAR(y[0], 1, 1e-15);
  EXPECT_EQ(y[1], 0.0);
}
