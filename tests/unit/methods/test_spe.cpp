// SPDX-License-Identifier: BSD-3-Clause
// [SPE] schemes (seed 003_b74f9306775dfa57.txt, METHODS §3.7): exactness the paper claims on
// lattices, the identities of its construction (Σ T̄ Δ = 0, S ≡ M up to a row factor on
// lattices, Brookshaw g1 = Morris), monotonicity, the consistent anisotropic form (R22)
// and the symmetrised smoothing length (26).
#include <cmath>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/spe/ingredients.hpp>
#include <vrsph/methods/spe/spe.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
// The [SPE] patch domain |x_a - 2.5| <= 1/2 with 21 particles per direction (dx = 0.05),
// support 2 f dx with f = 1.2 (METHODS §5.3), optionally perturbed.
struct Patch {
  PointCloud cloud;
  NeighbourList nl;
  Real support;
  Patch(int dim, Real delta, Real f = 1.2, int n = 20) {
    Domain box = Domain::unit_box(dim);
    for (int k = 0; k < dim; ++k) {
      box.lo[k] = 2;
      box.hi[k] = 3;
    }
    cloud = vertex_lattice(box, n);
    if (delta > 0) perturb(cloud, {delta, 7, false});
    support = 2 * f * cloud.spacing;
    SearchParams sp;
    sp.radius = support;
    nl = find_neighbours(cloud, sp);
  }
  Stencil build(const std::string& m, OperatorKind k, const MethodOptions& o = {}, const Field* a = nullptr,
                const Eigen::MatrixXd* mob = nullptr) const {
    StencilRequest req{k, a};
    req.mobility = mob;
    return builtin_methods().create(m, o)->build({cloud, nl, KernelType::CubicSplineSPE, cloud.spacing}, req);
  }
  Field eval(auto&& f) const {
    Field u(cloud.size());
    for (Index i = 0; i < u.size(); ++i) u[i] = f(cloud.positions[static_cast<std::size_t>(i)]);
    return u;
  }
  // Particles whose whole support lies inside the box (no truncated kernel).
  bool deep(Index i) const {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int k = 0; k < cloud.dim; ++k)
      if (x[k] - cloud.domain.lo[k] < support || cloud.domain.hi[k] - x[k] < support) return false;
    return true;
  }
  Real max_error_deep(const Field& got, auto&& exact) const {
    Real e = 0;
    for (Index i = 0; i < got.size(); ++i)
      if (deep(i)) e = std::max(e, std::abs(got[i] - exact(cloud.positions[static_cast<std::size_t>(i)])));
    return e;
  }
};

MethodOptions opts(std::initializer_list<std::pair<const char*, const char*>> kv) {
  MethodOptions o;
  for (const auto& [k, v] : kv) o.set(k, v);
  return o;
}
}  // namespace

TEST(SpeSchemes, CorrectedSchemesExactOnCubicsInsideTheLatticeForEveryGradientOption) {
  // METHODS §3.7.5 implementation check: ∇²(x³+y³) = 6x + 6y to round-off inside.
  const Patch p(2, 0);
  const Field u = p.eval([](const Vec3& x) { return x[0] * x[0] * x[0] + x[1] * x[1] * x[1]; });
  for (const auto* m : {"cb-sph", "s-sph", "m-sph"})
    for (const auto* g : {"g1", "g2", "g3", "g4"}) {
      const Field l = apply_component(p.build(m, OperatorKind::Laplacian, opts({{"gradient", g}})), u, 0);
      EXPECT_LT(p.max_error_deep(l, [](const Vec3& x) { return 6 * x[0] + 6 * x[1]; }), 1e-8) << m << " " << g;
    }
}

TEST(SpeSchemes, BrookshawWithG1AndScalarCoefficientIsMorris) {
  const Patch p(2, 0.2);
  const Field a = p.eval([](const Vec3& x) { return 1 + x[0] * x[1]; });
  const Stencil b = p.build("brookshaw", OperatorKind::DivAGrad, {}, &a);
  const Stencil s = p.build("sph", OperatorKind::DivAGrad, {}, &a);
  ASSERT_EQ(b.col, s.col);
  for (std::size_t k = 0; k < b.values[0].size(); ++k) EXPECT_NEAR(b.values[0][k], s.values[0][k], 1e-9 * std::abs(s.values[0][k]) + 1e-9);
}

TEST(SpeSchemes, MonotoneTransmissibilitiesCancelTheFirstMoment) {
  // Σ_J T̄_IJ Δ_J = 0 exactly for every gradient option (construction of (90)).
  const Patch p(2, 0.25);
  for (auto opt : {spe::GradientOption::G1, spe::GradientOption::G2, spe::GradientOption::G3, spe::GradientOption::G4}) {
    for (Index i : {0, 30, 220}) {
      spe::RowGeometry row;
      row.dim = 2;
      const auto nbr = p.nl.of(i);
      row.resize(nbr.size());
      const Kernel ker(KernelType::CubicSplineSPE, 2, p.support);
      const Real V = p.cloud.spacing * p.cloud.spacing;
      row.volume_self = V;
      row.W_self = ker.W(0);
      for (std::size_t k = 0; k < nbr.size(); ++k) {
        row.delta[k] = p.cloud.positions[static_cast<std::size_t>(nbr[k])] - p.cloud.positions[static_cast<std::size_t>(i)];
        row.r[k] = row.delta[k].norm();
        row.volume[k] = V;
        row.W[k] = ker.W(row.r[k]);
        row.dW_over_r[k] = ker.dW_over_r(row.r[k]);
      }
      spe::RowIngredients in;
      spe::compute_ingredients(row, opt, in);
      std::vector<Real> T;
      Eigen::Matrix3d gs;
      spe::monotone_transmissibilities(row, in, T, gs);
      Vec3 first = Vec3::Zero();
      Real scale = 0;
      for (std::size_t k = 0; k < T.size(); ++k) {
        first += T[k] * row.delta[k];
        scale += std::abs(T[k]) * row.r[k];
      }
      EXPECT_LT(first.norm(), 1e-12 * scale) << "particle " << i;
      // Corrected gradient: Σ V Δ^γ g*^α = δ_γα (25).
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (std::size_t k = 0; k < T.size(); ++k) M += row.volume[k] * row.delta[k] * in.gstar[k].transpose();
      EXPECT_LT((M.topLeftCorner(2, 2) - Eigen::Matrix2d::Identity()).norm(), 1e-12);
    }
  }
}

TEST(SpeSchemes, SchwaigerAndMonotoneDifferOnlyByARowFactorOnLattices) {
  // Remark 5: on uniform sets with radial gradients N = Ñ, so the brackets coincide.
  const Patch p(2, 0);
  const Stencil s = p.build("s-sph", OperatorKind::Laplacian);
  const Stencil m = p.build("m-sph", OperatorKind::Laplacian);
  for (Index i = 0; i < s.rows(); ++i) {
    const auto d = static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)]);
    const Real ratio = m.values[0][d] / s.values[0][d];
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k)
      EXPECT_NEAR(m.values[0][static_cast<std::size_t>(k)], ratio * s.values[0][static_cast<std::size_t>(k)],
                  1e-10 * std::abs(s.values[0][d]));
  }
}

TEST(SpeSchemes, MonotoneSchemeHasNonNegativeWeightsOnMildlyPerturbedClouds) {
  // (92)/(93) hold for small perturbations: every ξ·Δ_J < 1 and every off-diagonal >= 0.
  const Patch p(2, 0.1001);
  const Stencil m = p.build("m-sph", OperatorKind::Laplacian);
  for (Index i = 0; i < m.rows(); ++i) {
    if (!p.deep(i)) continue;
    EXPECT_LT(m.xi[static_cast<std::size_t>(i)], 1) << i;
    for (Index k = m.row_begin(i); k < m.row_end(i); ++k)
      if (m.col[static_cast<std::size_t>(k)] != i) {
        EXPECT_GT(m.values[0][static_cast<std::size_t>(k)], 0) << i;
      }
  }
}

TEST(SpeSchemes, ConsistentAnisotropyExactOnQuadraticsAndPaperFormIsNot) {
  // div(M grad u) for constant M = diag(m_1, .., m_d) and a quadratic u: Σ_k m_k u_kk.
  for (int dim = 2; dim <= 3; ++dim)
    for (Real delta : {0.0, 0.3}) {
      const Patch p(dim, delta, 1.2, dim == 3 ? 8 : 16);
      Eigen::MatrixXd M(p.cloud.size(), dim);
      for (int k = 0; k < dim; ++k) M.col(k).setConstant(1 + 3 * k);  // 1, 4, 7
      const Field u = p.eval([](const Vec3& x) { return x[0] * x[0] + x[0] * x[1] + 3 * x[1] * x[1] - x[1] * x[2] + 0.5 * x[2] * x[2]; });
      const Real exact = 2 * 1 + 6 * 4 + (dim == 3 ? 1 * 7 : 0);
      for (const auto* m : {"brookshaw", "cb-sph", "s-sph", "m-sph"}) {
        const Field c = apply_component(p.build(m, OperatorKind::DivAGrad, {}, nullptr, &M), u, 0);
        Real worst = 0;
        for (Index i = 0; i < c.size(); ++i)
          if (p.cloud.tags[static_cast<std::size_t>(i)] == Tag::Interior) worst = std::max(worst, std::abs(c[i] - exact));
        EXPECT_LT(worst, 1e-7 * exact) << m << " dim " << dim << " delta " << delta;
        if (delta == 0 && std::string(m) != "brookshaw") {
          // The printed weight converges to [tr H tr M + 2 tr(HM)]/(d+2): an O(1) error.
          const Field q = apply_component(p.build(m, OperatorKind::DivAGrad, opts({{"anisotropy", "paper"}}), nullptr, &M), u, 0);
          const Real trH = 2 + 6 + (dim == 3 ? 1 : 0), trM = 1 + 4 + (dim == 3 ? 7 : 0);
          const Real predicted = std::abs((trH * trM + 2 * exact) / (dim + 2) - exact);
          const Real err = p.max_error_deep(q, [&](const Vec3&) { return exact; });
          EXPECT_GT(err, 0.5 * predicted) << m << " dim " << dim;
          EXPECT_LT(err, 1.5 * predicted) << m << " dim " << dim;
        }
      }
    }
}

TEST(SpeSchemes, TensorMobilityRefusedByMethodsWithoutIt) {
  const Patch p(2, 0);
  Eigen::MatrixXd M = Eigen::MatrixXd::Ones(p.cloud.size(), 2);
  EXPECT_THROW(p.build("fpm", OperatorKind::DivAGrad, {}, nullptr, &M), ConfigError);
  M(5, 1) = -1;
  EXPECT_THROW_MSG(p.build("m-sph", OperatorKind::DivAGrad, {}, nullptr, &M), InputError, "particle 5");
  EXPECT_THROW(p.build("m-sph", OperatorKind::Laplacian, opts({{"gradient", "g5"}})), ConfigError);
}

TEST(SpeSchemes, SymmetrisedSmoothingLengthGivesSymmetricPairs) {
  // h̃_IJ = (h_I + h_J)/2 (26): J is a neighbour of I iff I is one of J.
  PointCloud c = vertex_lattice(Domain::unit_box(2), 12);
  perturb(c, {0.3, 3, false});
  SearchParams sp;
  sp.radii.resize(static_cast<std::size_t>(c.size()));
  for (Index i = 0; i < c.size(); ++i) sp.radii[static_cast<std::size_t>(i)] = (2 + c.positions[static_cast<std::size_t>(i)][0]) * c.spacing;
  sp.radius = 3 * c.spacing;
  const NeighbourList nl = find_neighbours(c, sp);
  const NeighbourList sym = symmetrised_pairs(c, nl);
  for (Index i = 0; i < sym.size(); ++i)
    for (Index j : sym.of(i)) {
      const auto row = sym.of(j);
      EXPECT_TRUE(std::binary_search(row.begin(), row.end(), i)) << i << " " << j;
    }
  const Stencil s = builtin_methods().create("m-sph")->build({c, nl, KernelType::CubicSplineSPE, c.spacing}, {OperatorKind::Laplacian});
  EXPECT_EQ(s.nnz(), sym.total() + sym.size());
}

TEST(SpeSchemes, SingularCorrectionMatrixNamesTheParticleOrFlagsTheRow) {
  // Particles 0..10 on a line: their A (and Γ) has no y-row, it is singular (METHODS X4).
  PointCloud c;
  c.dim = 2;
  c.spacing = 0.1;
  for (int k = 0; k <= 10; ++k) c.positions.emplace_back(0.1 * k, 0, 0);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) c.positions.emplace_back(5 + 0.1 * i, 5 + 0.1 * j, 0);
  c.tags.assign(c.positions.size(), Tag::Interior);
  SearchParams sp;
  sp.radius = 0.25;
  const NeighbourList nl = find_neighbours(c, sp);
  const Discretisation disc{c, nl, KernelType::CubicSplineSPE, c.spacing};
  EXPECT_THROW_MSG(builtin_methods().create("m-sph")->build(disc, {OperatorKind::Laplacian}), NumericalError, "particle");
  MethodOptions warn;
  warn.set("on_singular", "warn");
  const Stencil s = builtin_methods().create("s-sph", warn)->build(disc, {OperatorKind::Laplacian});
  ASSERT_EQ(s.local_failure.size(), c.positions.size());
  for (Index i = 0; i <= 10; ++i) EXPECT_TRUE(s.local_failure[static_cast<std::size_t>(i)]) << i;
  for (const auto& v : s.values)
    for (Real x : v) EXPECT_TRUE(std::isfinite(x));
  EXPECT_FALSE(s.local_failure[15]);
}

TEST(SpeSchemes, RowWithOnlyDimNeighboursFallsBackToTheBrookshawBracketAndIsReported) {
  // Particle 0 sees exactly two neighbours (2D): Σ T̄ Δ = 0 forces T̄ = 0, the corrected bracket
  // is round-off. S and M fall back to the pair term (positive weights) and flag the row.
  PointCloud c;
  c.dim = 2;
  c.spacing = 0.1;
  c.positions = {Vec3(0, 0, 0), Vec3(0.1, 0.02, 0), Vec3(-0.03, 0.09, 0), Vec3(0.5, 0.5, 0), Vec3(0.6, 0.5, 0),
                 Vec3(0.5, 0.6, 0), Vec3(0.42, 0.45, 0)};
  c.tags.assign(c.positions.size(), Tag::Interior);
  SearchParams sp;
  sp.radius = 0.125;
  sp.min_neighbours = 0;
  const NeighbourList nl = find_neighbours(c, sp);
  ASSERT_EQ(nl.count(0), 2);
  const Discretisation disc{c, nl, KernelType::CubicSplineSPE, c.spacing};
  // Particle 0 only: the others have one neighbour, a singular A, not this test's subject.
  const std::vector<char> rows = {1, 0, 0, 0, 0, 0, 0};
  ASSERT_EQ(rows.size(), c.positions.size());
  for (const auto* m : {"s-sph", "m-sph"}) {
    const Stencil s = builtin_methods().create(m)->build(disc, {OperatorKind::Laplacian, nullptr, nullptr, rows});
    EXPECT_EQ(s.residual[0], 1) << m;
    for (Index k = s.row_begin(0); k < s.row_end(0); ++k)
      if (s.col[static_cast<std::size_t>(k)] != 0) {
        EXPECT_GT(s.values[0][static_cast<std::size_t>(k)], 0) << m;
      }
  }
}
