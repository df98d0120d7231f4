// SPDX-License-Identifier: BSD-3-Clause
// NNLS: KKT conditions, agreement with brute-force enumeration of active sets and with
// the textbook reference, degenerate inputs (zero/duplicate columns, infeasible targets).
#include <Eigen/QR>
#include <array>
#include <cmath>
#include <random>
#include <vrsph/methods/vrsph/nnls.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
Eigen::MatrixXd random_matrix(int m, int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  Eigen::MatrixXd A(m, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) A(i, j) = g(rng);
  return A;
}

Eigen::VectorXd fast(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, NnlsResult* res = nullptr) {
  NnlsSolver s(2, 2);  // deliberately small: the workspace must grow on demand
  Eigen::VectorXd x(A.cols());
  const NnlsResult r = s.solve(A.data(), static_cast<int>(A.rows()), static_cast<int>(A.cols()), b.data(), x.data());
  if (res) *res = r;
  return x;
}

// KKT: x >= 0, w = A^T (b - A x) <= tol, and w_j = 0 where x_j > 0.
void expect_kkt(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x, double tol) {
  const Eigen::VectorXd w = A.transpose() * (b - A * x);
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    EXPECT_GE(x[j], 0.0);
    EXPECT_LE(w[j], tol);
    if (x[j] > 1e-12) {
      EXPECT_NEAR(w[j], 0.0, tol);
    }
  }
}

// A feasible target (b = A x0, x0 >= 0): NNLS converges to a zero residual and a KKT point.
NnlsResult expect_feasible_target_met(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double kkt_tol) {
  NnlsResult r;
  const Eigen::VectorXd x = fast(A, b, &r);
  EXPECT_EQ(r.status, NnlsStatus::Converged);
  EXPECT_LT(r.residual, 1e-10 * b.norm());
  expect_kkt(A, b, x, kkt_tol * b.norm());
  return r;
}

// Brute force: the best least-squares solution over every passive set whose
// unconstrained solution is non-negative.
double brute_force_residual(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const int n = static_cast<int>(A.cols());
  double best = b.norm();
  for (int mask = 1; mask < (1 << n); ++mask) {
    std::vector<int> cols;
    for (int j = 0; j < n; ++j)
      if (mask & (1 << j)) cols.push_back(j);
    Eigen::MatrixXd Ap(A.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t c = 0; c < cols.size(); ++c) Ap.col(static_cast<Eigen::Index>(c)) = A.col(cols[c]);
    const Eigen::VectorXd z = Ap.colPivHouseholderQr().solve(b);
    if (z.minCoeff() < 0) continue;
    best = std::min(best, (Ap * z - b).norm());
  }
  return best;
}
}  // namespace

TEST(Nnls, MatchesBruteForceEnumerationOnSmallRandomProblems) {
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 2 + trial % 6, n = 1 + (trial / 3) % 9;
    const Eigen::MatrixXd A = random_matrix(m, n, rng);
    const Eigen::VectorXd b = random_matrix(m, 1, rng).col(0);
    NnlsResult r;
    const Eigen::VectorXd x = fast(A, b, &r);
    SCOPED_TRACE(testing::Message() << "trial " << trial << " m=" << m << " n=" << n);
    ASSERT_EQ(r.status, NnlsStatus::Converged);
    EXPECT_NEAR(r.residual, (A * x - b).norm(), 1e-12);
    EXPECT_NEAR(r.residual, brute_force_residual(A, b), 1e-9 * (1 + b.norm()));
    expect_kkt(A, b, x, 1e-9);
    Eigen::VectorXd xr;
    nnls_reference(A, b, xr);
    EXPECT_NEAR((A * xr - b).norm(), r.residual, 1e-9);
  }
}

TEST(Nnls, WideProblemsLikeVrsphAgreeWithTheReference) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::MatrixXd A = random_matrix(12, 40 + trial, rng);
    // A feasible target: b = A x0 with x0 >= 0 sparse.
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(A.cols());
    for (int k = 0; k < 8; ++k) x0[(k * 7 + trial) % A.cols()] = 0.5 + k;
    const Eigen::VectorXd b = A * x0;
    NnlsResult r;
    const Eigen::VectorXd x = fast(A, b, &r);
    EXPECT_LT(r.residual, 1e-10 * b.norm());
    EXPECT_LE(r.passive, 12);
    expect_kkt(A, b, x, 1e-8 * b.norm());
  }
}

TEST(Nnls, EveryRowCountWithItsOwnCodeAgreesWithTheReference) {
  // The solver has code specialised for the row counts VRSPH's systems have (2D/3D point,
  // wall and compact rows: 2, 3, 7, 9, 10, 12, 15, 16, 19, 20, 27, 30, 35) and a generic path
  // for the others (13, 40): each on a feasible target (residual ~ 0, KKT) and on another
  // one (the reference's residual, KKT).
  std::mt19937 rng(11);
  for (const int m : {2, 3, 7, 9, 10, 12, 13, 15, 16, 19, 20, 27, 30, 35, 40}) {
    SCOPED_TRACE(m);
    const Eigen::MatrixXd A = random_matrix(m, 3 * m + 5, rng);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(A.cols());
    for (Eigen::Index k = 0; k < std::min<Eigen::Index>(m, 6); ++k) x0[(3 * k + 1) % A.cols()] = 1.0 + static_cast<double>(k);
    const Eigen::VectorXd b = A * x0;
    NnlsResult r = expect_feasible_target_met(A, b, 1e-8);
    // Another target, -b + a_0 (infeasible in general): the residual the reference reaches.
    Eigen::VectorXd xr;
    (void)nnls_reference(A, -b + A.col(0), xr, {});
    const Eigen::VectorXd xf = fast(A, -b + A.col(0), &r);
    EXPECT_NEAR(r.residual, (A * xr - (-b + A.col(0))).norm(), 1e-8 * b.norm());
    expect_kkt(A, -b + A.col(0), xf, 1e-8 * b.norm());
  }
}

TEST(Nnls, ColumnsLeavingALargePassiveSetKeepItsFactorsExact) {
  // A column that leaves the passive set updates R^-1 by the rotations that restore R
  // instead of recomputing it: over many departures from sets of up to m columns the answer
  // must stay an exact optimum. Moment systems as VRSPH's (rows: the monomials of degree
  // 1..4 of points in a ball, and their sum; 2D 15 rows, 3D 35 as the compact rows), whose
  // nearly parallel columns make Lawson-Hanson drop columns often (3D: ~30 times a solve).
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int departures = 0;
  for (const int dim : {2, 3}) {
    std::vector<std::array<int, 3>> powers;
    for (int a = 0; a <= 4; ++a)
      for (int b = 0; a + b <= 4; ++b)
        for (int c = 0; a + b + c <= 4 && (dim == 3 || c == 0); ++c)
          if (a + b + c >= 1) powers.push_back({a, b, c});
    const int m = static_cast<int>(powers.size()) + 1, n = dim == 2 ? 40 : 110;
    for (int trial = 0; trial < 10; ++trial) {
      SCOPED_TRACE(testing::Message() << "dim " << dim << " trial " << trial);
      Eigen::MatrixXd A(m, n);
      for (int j = 0; j < n; ++j) {
        std::array<double, 3> e{};
        do {
          for (int k = 0; k < dim; ++k) e[static_cast<std::size_t>(k)] = u(rng);
        } while (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] > 1);
        for (std::size_t r = 0; r < powers.size(); ++r)
          A(static_cast<Eigen::Index>(r), j) = std::pow(e[0], powers[r][0]) * std::pow(e[1], powers[r][1]) * std::pow(e[2], powers[r][2]);
        A(m - 1, j) = 1;
      }
      Eigen::VectorXd x0(n);
      for (int j = 0; j < n; ++j) x0[j] = 0.5 * (1 + u(rng));  // dense: a feasible target many vertices meet
      const NnlsResult r = expect_feasible_target_met(A, A * x0, 1e-9);
      // Each iteration adds a column or removes one: the surplus over the final set counts departures.
      departures += std::max(0, r.iterations - r.passive);
    }
  }
  EXPECT_GT(departures, 100);  // the path under test was taken
}

TEST(Nnls, DegenerateInputs) {
  // Zero and duplicate columns.
  Eigen::MatrixXd A(3, 5);
  A << 1, 0, 1, 2, 0,  //
      0, 0, 0, 1, 1,   //
      1, 0, 1, 0, 1;
  const Eigen::VectorXd b = Eigen::Vector3d(2, 1, 2);
  NnlsResult r;
  Eigen::VectorXd x = fast(A, b, &r);
  EXPECT_EQ(r.status, NnlsStatus::Converged);
  EXPECT_EQ(x[1], 0.0);  // the zero column never enters
  EXPECT_NEAR(r.residual, brute_force_residual(A, b), 1e-12);
  expect_kkt(A, b, x, 1e-12);
  // Infeasible target: every column points away from b -> x = 0, residual |b|.
  Eigen::MatrixXd B(2, 3);
  B << 1, 2, 0.5,  //
      1, 0, 3;
  const Eigen::VectorXd c = Eigen::Vector2d(-1, -1);
  x = fast(B, c, &r);
  EXPECT_EQ(x.norm(), 0.0);
  EXPECT_NEAR(r.residual, std::sqrt(2.0), 1e-15);
  // No columns at all.
  Eigen::MatrixXd E(2, 0);
  x = fast(E, c, &r);
  EXPECT_NEAR(r.residual, std::sqrt(2.0), 1e-15);
}

TEST(Nnls, IterationCapIsReported) {
  std::mt19937 rng(3);
  const Eigen::MatrixXd A = random_matrix(12, 60, rng);
  const Eigen::VectorXd b = A * Eigen::VectorXd::Ones(60);
  NnlsSolver s;
  Eigen::VectorXd x(60);
  NnlsOptions o;
  o.max_iterations = 2;
  const NnlsResult r = s.solve(A.data(), 12, 60, b.data(), x.data(), o);
  EXPECT_EQ(r.status, NnlsStatus::IterationLimit);
  EXPECT_GT(r.residual, 0.0);
  for (Eigen::Index j = 0; j < 60; ++j) EXPECT_GE(x[j], 0.0);
}

// A tie width makes the entering column independent of round-off: two columns whose
// multipliers differ only in the last bits (a symmetric pair, after a change of unit) give the
// first one every time, whichever round-off made larger; without it the larger enters.
TEST(Nnls, TieToleranceMakesTheEnteringColumnReproducible) {
  // b = (1, 1): columns 0 and 1 reach it alone (each exactly), their multipliers
  // A_j^T b differ by one ulp-scale step in either order.
  for (const Real bump : {1e-15, -1e-15}) {
    Eigen::MatrixXd A(2, 2);
    A << 1, 1 + bump,  //
        1, 1;
    const Eigen::VectorXd b = Eigen::Vector2d(1, 1);
    NnlsSolver s;
    Eigen::VectorXd x(2);
    NnlsOptions o;
    o.tie_tolerance = 1e-10;
    (void)s.solve(A.data(), 2, 2, b.data(), x.data(), o);
    EXPECT_GT(x[0], 0.5) << "bump " << bump;  // column 0 entered and carries the solution
    o.tie_tolerance = 0;
    (void)s.solve(A.data(), 2, 2, b.data(), x.data(), o);
    EXPECT_EQ(x[0] > 0.5, bump < 0) << "bump " << bump;  // the larger multiplier (round-off) decides
  }
}

// Warm start: from the optimal passive set the solver stops at once with the same x; from a
// wrong guess (columns that must leave, repeated and out-of-range ones) it still ends at an
// optimum (the residual of the cold start, KKT: w = A^T r <= tol off the passive set).
TEST(NnlsWarmStart, FromTheOptimalSetAtOnceFromAWrongOneAtAnOptimum) {
  std::mt19937 rng(3u);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const int m = 5 + trial % 4, n = 12 + trial % 20;
    Eigen::MatrixXd A(m, n);
    Eigen::VectorXd b(m);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < m; ++i) A(i, j) = g(rng);
    for (int i = 0; i < m; ++i) b[i] = g(rng);
    if (trial % 2 == 0) b = A * Eigen::VectorXd::Random(n).cwiseAbs();  // consistent: residual 0
    NnlsSolver solver;
    Eigen::VectorXd cold(n), warm(n), wrong(n);
    const NnlsResult rc = solver.solve(A.data(), m, n, b.data(), cold.data());
    std::vector<int> passive;
    for (int j = 0; j < n; ++j)
      if (cold[j] > 0) passive.push_back(j);
    const NnlsResult rw = solver.solve(A.data(), m, n, b.data(), warm.data(), {}, MatrixOrder::ColumnMajor, passive);
    EXPECT_EQ(rw.iterations, 0) << trial;
    EXPECT_EQ(rw.warm_kept, static_cast<int>(passive.size())) << trial;
    EXPECT_LT((warm - cold).norm(), 1e-9 * (1 + cold.norm())) << trial;
    std::vector<int> guess{0, 1, 2, 2, n + 3, -1, n - 1, 3, 4, 5};
    const NnlsResult rg = solver.solve(A.data(), m, n, b.data(), wrong.data(), {}, MatrixOrder::ColumnMajor, guess);
    EXPECT_EQ(rg.status, NnlsStatus::Converged);
    EXPECT_NEAR(rg.residual, rc.residual, 1e-9 * (1 + b.norm())) << trial;
    EXPECT_GE(wrong.minCoeff(), 0.0);
    const Eigen::VectorXd w = A.transpose() * (b - A * wrong);
    for (int j = 0; j < n; ++j)
      if (wrong[j] == 0) {
        EXPECT_LE(w[j], 1e-9 * A.cwiseAbs().maxCoeff() * (1 + b.norm())) << trial << " " << j;
      }
  }
}
