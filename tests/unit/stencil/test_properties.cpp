// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/Eigenvalues>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/properties.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct Problem {
  PointCloud cloud;
  NeighbourList nl;
  Stencil lap;
  std::vector<char> unknown;
};
Problem morris(int dim, int n, double delta, double a_scale = 1) {
  Problem p;
  p.cloud = vertex_lattice(Domain::unit_box(dim), n);
  if (delta > 0) perturb(p.cloud, {delta, 11, false});
  SearchParams sp;
  sp.radius = 3 * p.cloud.spacing;
  p.nl = find_neighbours(p.cloud, sp);
  Field a(p.cloud.size());
  for (Index i = 0; i < a.size(); ++i) a[i] = a_scale * (1 + p.cloud.positions[static_cast<std::size_t>(i)].squaredNorm());
  StencilRequest req{OperatorKind::DivAGrad, &a};
  p.lap = builtin_methods().create("sph")->build({p.cloud, p.nl, KernelType::CubicSpline, p.cloud.spacing}, req);
  for (auto t : p.cloud.tags) p.unknown.push_back(t == Tag::Interior);
  return p;
}
}  // namespace

// [QW] Thm 5.1: with a non-increasing kernel, a > 0 and v >= 0 the Morris operator
// gives a Z-matrix -L with non-negative row sums, and chained dominance via the boundary.
TEST(Properties, MorrisOperatorIsAnMMatrixIn1D2D3D) {
  for (int dim = 1; dim <= 3; ++dim)
    for (double delta : {0.0, 0.5}) {
      const Problem p = morris(dim, dim == 3 ? 6 : 12, delta);
      const MMatrixReport r = check_m_matrix(p.lap, p.unknown);
      EXPECT_TRUE(r.is_m_matrix()) << dim << "D delta=" << delta << ": " << r.summary();
      EXPECT_EQ(r.rows, p.cloud.count(Tag::Interior));
      const Field sums = row_sums(p.lap);
      double scale = 0;
      for (double v : p.lap.values[0]) scale = std::max(scale, std::abs(v));
      EXPECT_LT(sums.cwiseAbs().maxCoeff(), 1e-12 * scale);
    }
}

TEST(Properties, DetectsWrongSignsDominanceAndDisconnection) {
  Problem p = morris(2, 8, 0.0);
  // A positive off-diagonal entry of -L (negative L_ij between two unknowns).
  Stencil bad = p.lap;
  Index row = 40;
  for (Index k = bad.row_begin(row); k < bad.row_end(row); ++k)
    if (bad.col[static_cast<std::size_t>(k)] != row && p.unknown[static_cast<std::size_t>(bad.col[static_cast<std::size_t>(k)])]) {
      bad.values[0][static_cast<std::size_t>(k)] = -1.0;
      break;
    }
  MMatrixReport r = check_m_matrix(bad, p.unknown);
  EXPECT_FALSE(r.z_matrix);
  EXPECT_FALSE(r.is_m_matrix());
  EXPECT_EQ(r.first_violation, row);
  EXPECT_NE(r.summary().find("NOT an M-matrix"), std::string::npos);
  // No Dirichlet particle: every row has zero row sum -> nothing strictly dominant.
  std::vector<char> all(p.unknown.size(), 1);
  r = check_m_matrix(p.lap, all);
  EXPECT_FALSE(r.chained);
  EXPECT_EQ(static_cast<Index>(r.unreachable.size()), p.cloud.size());
  EXPECT_THROW_MSG(check_m_matrix(p.lap, std::vector<char>(3, 1)), InputError, "mask has 3 entries");
}

TEST(Properties, MonomialResidualsOfSph) {
  PointCloud c = cell_centred_lattice(Domain::symmetric_box(2, 1), 16, false, 4);
  SearchParams sp;
  sp.radius = 3 * c.spacing;
  const NeighbourList nl = find_neighbours(c, sp);
  const auto m = builtin_methods().create("sph");
  std::vector<char> rows;
  std::vector<Real> scale(static_cast<std::size_t>(c.size()), sp.radius);
  for (auto t : c.tags) rows.push_back(t == Tag::Interior);
  const Stencil lap = m->build({c, nl, KernelType::CubicSpline, c.spacing}, {OperatorKind::Laplacian});
  const auto res = monomial_residuals(lap, c, scale, 3, rows);
  ASSERT_EQ(res.size(), 10u);
  EXPECT_LT(res[0].max_residual, 1e-11);  // constants: exact (difference form)
  EXPECT_LT(res[1].max_residual, 1e-11);  // x, y: exact on a symmetric lattice
  EXPECT_LT(res[2].max_residual, 1e-11);
  // x^2: SPH Laplacian is not exact on a lattice at h = 3 dx (discretisation error), but close.
  EXPECT_GT(res[3].max_residual, 1e-6);
  EXPECT_LT(res[3].max_residual, 0.05);  // |L x^2 - 2| (order 2, degree 2: no scaling)
}

namespace {
// The periodic second difference on n points (spacing 1), with row `big` scaled by `factor`.
Stencil periodic_second_difference(Index n, Index big = -1, Real factor = 1) {
  Stencil s;
  s.kind = OperatorKind::Laplacian;
  s.dim = 1;
  s.values.assign(1, {});
  for (Index i = 0; i < n; ++i) {
    const Real f = i == big ? factor : 1;
    for (const auto& [j, w] : {std::pair{(i + n - 1) % n, 1.0}, std::pair{i, -2.0}, std::pair{(i + 1) % n, 1.0}}) {
      if (j == i) s.diag.push_back(static_cast<Index>(s.col.size()));
      s.col.push_back(j);
      s.values[0].push_back(f * w);
    }
    s.row_ptr.push_back(static_cast<Index>(s.col.size()));
  }
  return s;
}
}  // namespace

TEST(SpectralRadius, ClusteredTopFromBelowWithinItsWidthAndAnIsolatedRowExactly) {
  // Eigenvalues -4 sin²(πk/n): ρ = 4 at k = n/2 with neighbours 4 cos²(π/n) below it, a cluster
  // power iteration approaches from below.
  const Index n = 64;
  const std::vector<char> all(static_cast<std::size_t>(n), 1);
  const Real rho = spectral_radius(periodic_second_difference(n), all);
  EXPECT_LE(rho, 4 * (1 + 1e-12));
  EXPECT_GT(rho, 0.98 * 4);
  // One row ten times the others: an isolated eigenvalue near -20, found to round-off.
  const Stencil one = periodic_second_difference(n, 7, 10);
  const Real isolated = spectral_radius(one, all);
  // F T (F the row scales, T symmetric) has the eigenvalues of the symmetric F^½ T F^½.
  const Stencil plain = periodic_second_difference(n);
  Eigen::MatrixXd sym = Eigen::MatrixXd::Zero(n, n);
  auto scale = [](Index i) { return i == 7 ? std::sqrt(10.0) : 1.0; };
  for (Index i = 0; i < n; ++i)
    for (Index k = plain.row_begin(i); k < plain.row_end(i); ++k) {
      const Index j = plain.col[static_cast<std::size_t>(k)];
      sym(i, j) += scale(i) * plain.values[0][static_cast<std::size_t>(k)] * scale(j);
    }
  const Real exact = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym).eigenvalues().cwiseAbs().maxCoeff();
  EXPECT_NEAR(isolated, exact, 1e-8 * exact);
  // Inactive rows and columns are data: only the active block counts.
  std::vector<char> half(static_cast<std::size_t>(n), 0);
  for (Index i = 0; i < 7; ++i) half[static_cast<std::size_t>(i)] = 1;  // row 7 (the big one) left out
  EXPECT_LT(spectral_radius(one, half), 4);
  EXPECT_EQ(spectral_radius(one, half), spectral_radius(one, half));  // deterministic
  EXPECT_THROW(spectral_radius(one, all, 0), ConfigError);
}
