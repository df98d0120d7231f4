// SPDX-License-Identifier: BSD-3-Clause
// Operators on moving particles. Without the warm start every update equals a fresh build
// on the same positions bit for bit, entry for entry apart from the explicit zeros a VRSPH
// rebuild does not store (VRSPH, SPH, FPM). With it VRSPH's rows reach the same
// NNLS optimum (the same residuals to the tolerance), so they stay exact on quadratics
// (Laplacian) and linears (gradient, divergence) with -L's sign structure, while most rows'
// guesses hold. A failed update leaves the operators as they were.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/moving/operators.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {

StudyCloud operators_cloud(int dim, const std::string& periodic = "", int n = 0, std::uint64_t seed = 9) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(dim);
  spec.box.set_periodic(periodic);
  spec.n = n > 0 ? n : dim == 3 ? 10 : 24;
  spec.seed = seed;
  return make_study_cloud(spec);
}

// One step of a divergence-free cellular flow whose normal velocity vanishes on the unit
// box's faces (the boundary particles stay put); wrapped into a periodic box.
std::vector<Vec3> advect(const PointCloud& c, Real dt) {
  std::vector<Vec3> x = c.positions;
  for (Index i = 0; i < c.size(); ++i) {
    if (c.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    Vec3& p = x[static_cast<std::size_t>(i)];
    const Vec3 u(std::sin(std::numbers::pi * p[0]) * std::cos(std::numbers::pi * p[1]), -std::cos(std::numbers::pi * p[0]) * std::sin(std::numbers::pi * p[1]), 0);
    p += dt * u;
    if (c.dim == 3) p[2] += dt * 0.3 * std::sin(std::numbers::pi * p[2]);
    p = c.domain.wrap(p);
  }
  return x;
}

// The entries of a stencil other than explicit zeros (the diagonal always): a rebuild stores only
// the entries with a volume, a fresh build the whole neighbour pattern.
Stencil without_zeros(const Stencil& s) {
  Stencil out;
  out.values.resize(s.values.size());
  for (Index i = 0; i < s.rows(); ++i) {
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
      const auto sk = static_cast<std::size_t>(k);
      bool keep = s.col[sk] == i;
      for (const auto& v : s.values) keep = keep || v[sk] != 0;
      if (!keep) continue;
      out.col.push_back(s.col[sk]);
      for (std::size_t c = 0; c < s.values.size(); ++c) out.values[c].push_back(s.values[c][sk]);
    }
    out.row_ptr.push_back(static_cast<Index>(out.col.size()));
  }
  out.residual = s.residual;
  return out;
}

void expect_same_stencil(const Stencil& x, const Stencil& y) {
  const Stencil a = without_zeros(x), b = without_zeros(y);
  ASSERT_EQ(a.row_ptr, b.row_ptr);
  ASSERT_EQ(a.col, b.col);
  ASSERT_EQ(a.values.size(), b.values.size());
  for (std::size_t c = 0; c < a.values.size(); ++c) ASSERT_EQ(a.values[c], b.values[c]) << "component " << c;  // bitwise
  EXPECT_EQ(a.residual, b.residual);
}
}  // namespace

class MovingOperatorsCold : public ::testing::TestWithParam<std::string> {};

TEST_P(MovingOperatorsCold, EveryUpdateEqualsAFreshBuild) {
  const StudyCloud sc = operators_cloud(2);
  OperatorsOptions o;
  o.method = GetParam();
  o.warm_start = false;
  o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient, OperatorKind::Hessian};
  Operators ops(sc.cloud, o);
  const auto method = builtin_methods().create(GetParam());
  for (int step = 0; step < 6; ++step) {
    const std::vector<Vec3> x = advect(ops.cloud(), 0.004);
    ops.update(x);
    SearchParams sp;
    sp.radius = ops.radius();
    const NeighbourList nl = find_neighbours(ops.cloud(), sp);
    const Discretisation disc{ops.cloud(), nl, KernelType::CubicSpline, ops.spacing()};
    for (const OperatorKind k : {OperatorKind::Laplacian, OperatorKind::Gradient, OperatorKind::Hessian})
      expect_same_stencil(ops.stencil(k), build_stencil(*method, disc, {k}));
  }
  EXPECT_GE(ops.stats().updates, 6);
  EXPECT_LT(ops.stats().searches, 7);  // the skin saved searches
}

INSTANTIATE_TEST_SUITE_P(Methods, MovingOperatorsCold, ::testing::Values("vrsph", "sph", "fpm"));

TEST(MovingOperators, PerParticleRadiiGiveTheStencilsOfAFreshBuildWithThem) {
  // set_support_radii (a flow's grown supports): every row then reads its own radius. Against
  // build_stencil on find_neighbours with the same radii (bit for bit, cold); on a periodic box
  // FPM's rows are built on the images with them (to round-off, as above).
  for (const std::string periodic : {"", "x,y"}) {
    for (const std::string name : {"vrsph", "fpm"}) {
      const StudyCloud sc = operators_cloud(2, periodic);
      OperatorsOptions o;
      o.method = name;
      o.warm_start = false;
      Operators ops(sc.cloud, o);
      std::vector<Real> radii(static_cast<std::size_t>(ops.cloud().size()));
      for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = (i % 2 ? 1.3 : 1.0) * ops.radius();
      ops.set_support_radii(radii);
      EXPECT_EQ(ops.radius(), ops.support_radii().front());  // the base radius stays
      const auto method = builtin_methods().create(name);
      for (int step = 0; step < 2; ++step) {
        ops.update(advect(ops.cloud(), 0.004));
        EXPECT_EQ(ops.support_radii(), radii);
        SearchParams sp;
        sp.radius = ops.radius();
        sp.radii = radii;
        for (const OperatorKind k : {OperatorKind::Laplacian, OperatorKind::Gradient}) {
          if (periodic.empty() || name == "vrsph") {
            const NeighbourList nl = find_neighbours(ops.cloud(), sp);
            const Discretisation disc{ops.cloud(), nl, KernelType::CubicSpline, ops.spacing()};
            expect_same_stencil(ops.stencil(k), build_stencil(*method, disc, {k}));
          } else {
            const Stencil images = periodic_stencil(*method, ops.cloud(), sp, KernelType::CubicSpline, ops.spacing(), {k});
            for (std::size_t c = 0; c < images.values.size(); ++c) {
              const SparseMatrix a(as_eigen(ops.stencil(k), static_cast<int>(c))), b(as_eigen(images, static_cast<int>(c)));
              EXPECT_LT((a - b).norm(), 1e-10 * b.norm()) << name << " step " << step;
            }
          }
        }
      }
      EXPECT_THROW_MSG(ops.set_support_radii({1.0}), InputError, "radii for");
    }
  }
}

class MovingOperatorsWarm : public ::testing::TestWithParam<int> {};

TEST_P(MovingOperatorsWarm, VrsphRowsStayExactAndMonotone) {
  const int dim = GetParam();
  const StudyCloud sc = operators_cloud(dim);
  OperatorsOptions o;
  Operators ops(sc.cloud, o);
  const auto method = builtin_methods().create("vrsph");
  Index rows = 0, hits = 0;
  for (int step = 0; step < 5; ++step) {
    ops.update(advect(ops.cloud(), 0.01));
    const PointCloud& c = ops.cloud();
    rows += ops.stats().warm_rows;
    hits += ops.stats().warm_hits;
    SearchParams sp;
    sp.radius = ops.radius();
    const NeighbourList nl = find_neighbours(c, sp);
    const Stencil fresh = method->build({c, nl, KernelType::CubicSpline, ops.spacing()}, {OperatorKind::Laplacian});
    const Stencil& lap = ops.stencil(OperatorKind::Laplacian);
    Field q(c.size()), lin(c.size());
    Eigen::MatrixXd U(c.size(), dim);
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& p = c.positions[static_cast<std::size_t>(i)];
      q[i] = p[0] * p[0] + p[0] * p[1] + 2 * p[1] * p[1] - p[2] * p[2];  // Laplacian 4
      lin[i] = 2 * p[0] - p[1] + 0.5 * p[2];
      for (int k = 0; k < dim; ++k) U(i, k) = (k + 1.0) * p[(k + 1) % dim] - 0.5 * k * p[k];  // divergence -(0+1+..)/2
    }
    const Eigen::MatrixXd Lq = ops.apply(OperatorKind::Laplacian, q), G = ops.apply(OperatorKind::Gradient, lin);
    const Eigen::MatrixXd div = ops.apply(VectorOperator::Divergence, U);
    const Real div_exact = -0.25 * (dim - 1) * dim;  // -(0 + 1 + ... + (dim - 1)) / 2
    for (Index i = 0; i < c.size(); ++i) {
      if (c.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
      const auto si = static_cast<std::size_t>(i);
      EXPECT_NEAR(lap.residual[si], fresh.residual[si], 1e-9) << "row " << i;  // one optimum value
      for (Index k = lap.row_begin(i); k < lap.row_end(i); ++k)
        if (k != lap.diag[si]) {
          EXPECT_GE(lap.values[0][static_cast<std::size_t>(k)], 0.0);
        }
      if (fresh.residual[si] > 1e-10) continue;  // a row whose moments no v >= 0 meets
      EXPECT_NEAR(Lq(i, 0), dim == 3 ? 4.0 : 6.0, 1e-6) << "row " << i;
      const Stencil& g = ops.stencil(OperatorKind::Gradient);
      if (g.residual[si] > 1e-10) continue;
      EXPECT_NEAR(G(i, 0), 2, 1e-7);
      EXPECT_NEAR(G(i, 1), -1, 1e-7);
      EXPECT_NEAR(div(i, 0), div_exact, 1e-7);
    }
  }
  EXPECT_GT(rows, 0);
  EXPECT_GT(hits, rows / 2) << hits << " of " << rows << " warm starts held";
}

INSTANTIATE_TEST_SUITE_P(Dimensions, MovingOperatorsWarm, ::testing::Values(2, 3));

// With a warm start the gradient rows take the Laplacian's volumes where these meet the Laplace
// conditions (which contain the gradient's) and the support reaches no wall particle: an optimum
// of the gradient's own NNLS. [QW]'s rows
// (gradient_order=2) are those volumes times the kernel gradient, so they must stay exact on
// quadratics; the Laplacian is untouched (bit for bit the stencil of operators that share
// nothing), and the Laplacian is built first whatever the order the operators were asked in.
TEST_P(MovingOperatorsWarm, GradientRowsBorrowTheLaplaciansVolumesAndStayExact) {
  const int dim = GetParam();
  const StudyCloud sc = operators_cloud(dim);
  OperatorsOptions o;
  o.method_options = MethodOptions::parse({"gradient_order=2"});
  o.operators = {OperatorKind::Gradient, OperatorKind::Laplacian};
  Operators shared(sc.cloud, o);
  o.share_volumes = false;
  Operators own(sc.cloud, o);
  Index borrowed = 0, away = 0, exact_rows = 0;
  for (int step = 0; step < 4; ++step) {
    const std::vector<Vec3> x = advect(shared.cloud(), 0.01);
    shared.update(x);
    own.update(x);
    EXPECT_EQ(own.stats().borrowed_rows, 0);
    // The rows whose support reaches no wall: the only ones that may borrow.
    const NeighbourList& nl = shared.neighbours();
    Index away_now = 0;
    for (Index i = 0; i < nl.size(); ++i) {
      const auto of = nl.of(i);
      away_now += std::none_of(of.begin(), of.end(), [&](Index j) {
        const Tag t = shared.cloud().tags[static_cast<std::size_t>(j)];
        return t == Tag::Dirichlet || t == Tag::Neumann;
      }) ? 1 : 0;
    }
    EXPECT_LE(shared.stats().borrowed_rows, away_now) << "step " << step;
    away += away_now;
    borrowed += shared.stats().borrowed_rows;
    expect_same_stencil(shared.stencil(OperatorKind::Laplacian), own.stencil(OperatorKind::Laplacian));
    const PointCloud& c = shared.cloud();
    Field q(c.size());
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& p = c.positions[static_cast<std::size_t>(i)];
      q[i] = p[0] * p[0] - 3 * p[0] * p[1] + 2 * p[1] * p[1] + p[2] * p[2] + p[1] * p[2];
    }
    const Eigen::MatrixXd G = shared.apply(OperatorKind::Gradient, q);
    const Stencil& g = shared.stencil(OperatorKind::Gradient);
    for (Index i = 0; i < c.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (c.tags[si] != Tag::Interior || g.residual[si] > 1e-10) continue;
      const Vec3& p = c.positions[si];
      EXPECT_NEAR(G(i, 0), 2 * p[0] - 3 * p[1], 1e-7) << "row " << i;
      EXPECT_NEAR(G(i, 1), -3 * p[0] + 4 * p[1] + p[2], 1e-7) << "row " << i;
      if (dim == 3) {
        EXPECT_NEAR(G(i, 2), 2 * p[2] + p[1], 1e-7) << "row " << i;
      }
      ++exact_rows;
    }
  }
  // Away from walls nearly every row's Laplace moments have a non-negative solution: it borrows.
  std::cout << dim << "D: " << borrowed << " rows borrowed of " << away << " away from walls over 4 updates\n";
  EXPECT_GT(away, 0);
  EXPECT_GE(borrowed, away * 9 / 10) << borrowed << " rows borrowed of " << away << " away from walls";
  EXPECT_GT(exact_rows, 0);
}

// On a periodic box, rows that read only pair vectors and distances — SPH's (since 2026-12-07;
// before, they were built on the images at every update), FPM's with v = dx^d and the Hessian
// rows — read the minimum-image list (the Verlet skin) and equal periodic_stencil's image-cloud
// rows to round-off (the summation order differs, and the skin's pairs are zeros). The [SPE]
// schemes' rows, which read more than their pairs, are still built on the images, bit for bit those.
TEST(MovingOperators, PeriodicBoxesBuildOnTheImagesOrReadTheMinimumImages) {
  {
    const StudyCloud sc = operators_cloud(2, "x,y");
    OperatorsOptions o;
    o.method = "brookshaw";
    o.operators = {OperatorKind::Laplacian};
    Operators ops(sc.cloud, o);
    ops.update(advect(ops.cloud(), 0.05));
    SearchParams sp;
    sp.radius = ops.radius();
    const auto method = builtin_methods().create("brookshaw");
    expect_same_stencil(ops.stencil(OperatorKind::Laplacian),
                        periodic_stencil(*method, ops.cloud(), sp, KernelType::CubicSpline, ops.spacing(), {OperatorKind::Laplacian}));
  }
  for (const std::string name : {"sph", "fpm"}) {
    const StudyCloud sc = operators_cloud(2, "x,y");
    OperatorsOptions o;
    o.method = name;
    o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient, OperatorKind::Hessian};
    Operators ops(sc.cloud, o);
    const auto method = builtin_methods().create(name);
    for (int step = 0; step < 3; ++step) {
      ops.update(advect(ops.cloud(), 0.05));
      SearchParams sp;
      sp.radius = ops.radius();
      const Stencil images =
          periodic_stencil(*method, ops.cloud(), sp, KernelType::CubicSpline, ops.spacing(), {OperatorKind::Laplacian});
      const SparseMatrix moving(as_eigen(ops.stencil(OperatorKind::Laplacian))), fresh(as_eigen(images));
      EXPECT_LT((moving - fresh).norm(), 1e-10 * fresh.norm()) << name << " step " << step;
      const Stencil hessian =
          periodic_stencil(*method, ops.cloud(), sp, KernelType::CubicSpline, ops.spacing(), {OperatorKind::Hessian});
      for (int c = 0; c < 3; ++c) {
        const SparseMatrix a(as_eigen(ops.stencil(OperatorKind::Hessian), c)), b(as_eigen(hessian, c));
        EXPECT_LT((a - b).norm(), 1e-10 * b.norm()) << name << " step " << step << " component " << c;
      }
    }
  }
}

// A periodic box moved by a flow that crosses its faces (u = (0.5 + sin 2πy, cos 2πx)): VRSPH's
// point rows read the minimum-image list directly (skin, warm start). Each row meets its moment
// conditions across the faces — Σ_j w_ij d_ij = 0 and Σ_j w_ij d_ij d_ijᵀ = 2 I for the Laplacian,
// Σ_j g_ij d_ijᵀ = I for the gradient, d_ij the minimum-image vector — with residuals equal to
// those of periodic_stencil's image-cloud build on the same positions.
TEST(MovingOperators, VrsphOnAPeriodicBoxMeetsItsMomentsAcrossTheFaces) {
  const StudyCloud sc = operators_cloud(2, "x,y");
  Operators ops(sc.cloud, {});
  const auto method = builtin_methods().create("vrsph");
  Index rows = 0, hits = 0;
  for (int step = 0; step < 4; ++step) {
    std::vector<Vec3> x = ops.cloud().positions;
    for (Vec3& p : x) p = ops.cloud().domain.wrap(p + 0.004 * Vec3(0.5 + std::sin(2 * std::numbers::pi * p[1]), std::cos(2 * std::numbers::pi * p[0]), 0));
    ops.update(x);
    rows += ops.stats().warm_rows;
    hits += ops.stats().warm_hits;
    const PointCloud& c = ops.cloud();
    SearchParams sp;
    sp.radius = ops.radius();
    const Stencil images = periodic_stencil(*method, c, sp, KernelType::CubicSpline, ops.spacing(), {OperatorKind::Laplacian});
    const Stencil& lap = ops.stencil(OperatorKind::Laplacian);
    const Stencil& grad = ops.stencil(OperatorKind::Gradient);
    auto image_vector = [&](Index i, Index j) {
      Vec3 d = c.positions[static_cast<std::size_t>(j)] - c.positions[static_cast<std::size_t>(i)];
      for (int k = 0; k < 2; ++k) d[k] -= std::round(d[k]);  // period 1
      return d;
    };
    for (Index i = 0; i < c.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      EXPECT_NEAR(lap.residual[si], images.residual[si], 1e-9) << "row " << i;
      Eigen::Matrix2d second = Eigen::Matrix2d::Zero(), g = Eigen::Matrix2d::Zero();
      Eigen::Vector2d first = Eigen::Vector2d::Zero();
      for (Index k = lap.row_begin(i); k < lap.row_end(i); ++k) {
        const Eigen::Vector2d d = image_vector(i, lap.col[static_cast<std::size_t>(k)]).head<2>();
        first += lap.values[0][static_cast<std::size_t>(k)] * d;
        second += lap.values[0][static_cast<std::size_t>(k)] * d * d.transpose();
      }
      for (Index k = grad.row_begin(i); k < grad.row_end(i); ++k) {
        const Eigen::Vector2d d = image_vector(i, grad.col[static_cast<std::size_t>(k)]).head<2>();
        const Eigen::Vector2d w(grad.values[0][static_cast<std::size_t>(k)], grad.values[1][static_cast<std::size_t>(k)]);
        g += w * d.transpose();
      }
      if (lap.residual[si] < 1e-10) {
        EXPECT_LT(first.norm(), 1e-8) << "row " << i;
        EXPECT_LT((second - 2 * Eigen::Matrix2d::Identity()).norm(), 1e-8) << "row " << i;
      }
      if (grad.residual[si] < 1e-10) {
        EXPECT_LT((g - Eigen::Matrix2d::Identity()).norm(), 1e-8) << "row " << i;
      }
    }
  }
  EXPECT_GT(hits, rows / 2) << hits << " of " << rows;
}

TEST(MovingOperators, AFailedUpdateLeavesTheOperatorsAsTheyWere) {
  const StudyCloud sc = operators_cloud(2);
  Operators ops(sc.cloud, {});
  ops.update(advect(ops.cloud(), 0.01));
  const Stencil before = ops.stencil(OperatorKind::Laplacian);
  std::vector<Vec3> x = advect(ops.cloud(), 0.01);
  x.pop_back();
  EXPECT_THROW(ops.update(x), InputError);
  x = advect(ops.cloud(), 0.01);
  x[10][0] = std::nan("");
  EXPECT_THROW(ops.update(x), InputError);
  x[10] = x[11];  // a duplicate
  EXPECT_THROW(ops.update(x), InputError);
  x = ops.cloud().positions;
  x[12][2] = 0.1;  // a z coordinate in 2D
  EXPECT_THROW(ops.update(x), InputError);
  expect_same_stencil(ops.stencil(OperatorKind::Laplacian), before);
  EXPECT_EQ(ops.stats().updates, 1);
  OperatorsOptions bad;
  bad.operators = {OperatorKind::DivAGrad};
  EXPECT_THROW(Operators(sc.cloud, bad), ConfigError);
  bad.operators = {OperatorKind::Laplacian, OperatorKind::Laplacian};
  EXPECT_THROW(Operators(sc.cloud, bad), ConfigError);
  bad = {};
  bad.skin = -0.1;
  EXPECT_THROW(Operators(sc.cloud, bad), ConfigError);
  EXPECT_THROW(ops.stencil(OperatorKind::Dx), ConfigError);
}

// Marked rows (a flow's free surface): their first-derivative rows from marked_gradient_method,
// the others from the gradient's method, on the box and on a periodic one (built on the images),
// kept through updates; the Laplacian untouched; unmarked again, the plain rows.
TEST(MovingOperators, MarkedRowsTakeTheirOwnGradientMethodThroughUpdates) {
  for (const std::string periodic : {"", "x"}) {
    const StudyCloud sc = operators_cloud(2, periodic);
    OperatorsOptions o;
    o.warm_start = false;
    o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient, OperatorKind::Dx};
    o.gradient_method = "fpm";
    o.gradient_method_options.set("gradient_order", "2");
    o.marked_gradient_method = "fpm";
    o.marked_gradient_method_options.set("gradient_order", "1");
    Operators ops(sc.cloud, o);
    const Stencil laplacian = ops.stencil(OperatorKind::Laplacian);
    std::vector<char> marked(static_cast<std::size_t>(ops.cloud().size()), 0);
    for (std::size_t i = 0; i < marked.size(); ++i) marked[i] = ops.cloud().positions[i][1] > 0.8;  // a top band
    ops.set_marked_rows(marked);
    EXPECT_EQ(ops.marked_rows(), marked);
    expect_same_stencil(ops.stencil(OperatorKind::Laplacian), laplacian);
    for (int step = 0; step < 3; ++step) {
      if (step > 0) ops.update(advect(ops.cloud(), 0.004));
      Operators quadratic(ops.cloud(), [&] { OperatorsOptions q = o; q.marked_gradient_method.clear(); return q; }());
      OperatorsOptions lo = o;
      lo.gradient_method_options.set("gradient_order", "1");
      lo.marked_gradient_method.clear();
      const Operators linear(ops.cloud(), lo);
      for (const OperatorKind k : {OperatorKind::Gradient, OperatorKind::Dx}) {
        Field u(ops.cloud().size());
        for (Index i = 0; i < u.size(); ++i) u[i] = std::sin(2.0 * i) + ops.cloud().positions[static_cast<std::size_t>(i)][0];
        const Eigen::MatrixXd got = ops.apply(k, u), q = quadratic.apply(k, u), l = linear.apply(k, u);
        for (Index i = 0; i < u.size(); ++i)
          for (Index c = 0; c < got.cols(); ++c)
            EXPECT_EQ(got(i, c), marked[static_cast<std::size_t>(i)] ? l(i, c) : q(i, c)) << periodic << " step " << step;
      }
      // Both fits are exact on a linear field (along y alone on the box periodic in x).
      const Real ax = periodic.empty() ? 2 : 0;
      Field x(ops.cloud().size());
      for (Index i = 0; i < x.size(); ++i) {
        const Vec3& p = ops.cloud().positions[static_cast<std::size_t>(i)];
        x[i] = ax * p[0] - p[1];
      }
      const Eigen::MatrixXd g = ops.apply(OperatorKind::Gradient, x);
      for (Index i = 0; i < x.size(); ++i) {
        EXPECT_NEAR(g(i, 0), ax, 1e-9);
        EXPECT_NEAR(g(i, 1), -1, 1e-9);
      }
    }
    ops.set_marked_rows({});
    Operators plain(ops.cloud(), [&] { OperatorsOptions q = o; q.marked_gradient_method.clear(); return q; }());
    expect_same_stencil(ops.stencil(OperatorKind::Gradient), plain.stencil(OperatorKind::Gradient));
    EXPECT_THROW_MSG(ops.set_marked_rows({1, 0}), InputError, "2 marked-row flags for");
    EXPECT_TRUE(ops.marked_rows().empty());  // nothing changed
  }
  const StudyCloud sc = operators_cloud(2);
  Operators without(sc.cloud, {});
  without.set_marked_rows(std::vector<char>(static_cast<std::size_t>(sc.cloud.size()), 0));  // none marked: fine
  EXPECT_THROW_MSG(without.set_marked_rows(std::vector<char>(static_cast<std::size_t>(sc.cloud.size()), 1)), ConfigError,
                   "no marked_gradient_method");
  OperatorsOptions bad;
  bad.marked_gradient_method = "nonesuch";
  EXPECT_THROW(Operators(sc.cloud, bad), ConfigError);
}

namespace {
// A smooth positive coefficient at the particles' current places.
Field smooth_coefficient(const PointCloud& c, Real scale = 1) {
  Field a(c.size());
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& p = c.positions[static_cast<std::size_t>(i)];
    a[i] = scale * (1 + 0.5 * std::sin(3 * p[0]) * std::cos(2 * p[1]) + 0.2 * p[2]);
  }
  return a;
}
}  // namespace

// div(a grad) on moving particles, a carried by its particle: without the warm start every update
// equals a fresh build with the same a bit for bit (VRSPH, SPH, FPM; on a periodic box too, where
// SPH and FPM are built on the images with a copied to them).
TEST(MovingOperators, DivAGradUpdatesEqualAFreshBuildWithTheCoefficient) {
  for (const std::string periodic : {"", "x,y"})
    for (const std::string name : {"vrsph", "sph", "fpm"}) {
      const StudyCloud sc = operators_cloud(2, periodic);
      OperatorsOptions o;
      o.method = name;
      o.warm_start = false;
      o.operators = {OperatorKind::DivAGrad, OperatorKind::Laplacian};
      o.coefficient = smooth_coefficient(sc.cloud);
      Operators ops(sc.cloud, o);
      const auto method = builtin_methods().create(name);
      for (int step = 0; step < 3; ++step) {
        const std::vector<Vec3> x = advect(ops.cloud(), 0.004);
        if (step == 1) {
          PointCloud moved = ops.cloud();
          moved.positions = x;
          ops.update(x, smooth_coefficient(moved, 2));  // a new a with the new places
        } else {
          ops.update(x);  // a moves with its particle
        }
        const Field& a = ops.coefficient();
        SearchParams sp;
        sp.radius = ops.radius();
        StencilRequest req{OperatorKind::DivAGrad, &a};
        if (!periodic.empty() && name != "vrsph") {
          const Stencil images = periodic_stencil(*method, ops.cloud(), sp, KernelType::CubicSpline, ops.spacing(), req);
          const SparseMatrix m(as_eigen(ops.stencil(OperatorKind::DivAGrad), 0)), e(as_eigen(images, 0));
          EXPECT_LT((m - e).norm(), 1e-12 * e.norm()) << name << " step " << step;
          continue;
        }
        sp.wrap_periodic = true;
        const NeighbourList nl = find_neighbours(ops.cloud(), sp);
        const Discretisation disc{ops.cloud(), nl, KernelType::CubicSpline, ops.spacing()};
        expect_same_stencil(ops.stencil(OperatorKind::DivAGrad), build_stencil(*method, disc, req));
      }
    }
}

// With the warm start VRSPH's div(a grad) point rows take all the Laplacian's volumes (the same
// NNLS; a enters only the weights as a pair mean): with a = 1 the rows are the Laplacian's bit for
// bit, with a constant a its multiple (exact on quadratics), and with a smooth a the residuals are
// those of the rows' own NNLS.
TEST(MovingOperators, VrsphDivAGradTakesTheLaplaciansVolumes) {
  const StudyCloud sc = operators_cloud(2);
  OperatorsOptions o;
  o.operators = {OperatorKind::DivAGrad, OperatorKind::Laplacian};
  o.coefficient = Field::Ones(sc.cloud.size());
  Operators ones(sc.cloud, o);
  o.coefficient = Field::Constant(sc.cloud.size(), 2.5);
  Operators constant(sc.cloud, o);
  o.coefficient = smooth_coefficient(sc.cloud);
  Operators smooth(sc.cloud, o);
  o.share_volumes = false;
  Operators own(sc.cloud, o);
  for (int step = 0; step < 3; ++step) {
    const std::vector<Vec3> x = advect(ones.cloud(), 0.01);
    for (Operators* ops : {&ones, &constant, &smooth, &own}) ops->update(x);
    const Index n = ones.cloud().size();
    EXPECT_EQ(ones.stats().borrowed_rows, n);
    EXPECT_EQ(own.stats().borrowed_rows, 0);
    const Stencil& lap = ones.stencil(OperatorKind::Laplacian);
    expect_same_stencil(ones.stencil(OperatorKind::DivAGrad), lap);
    const PointCloud& c = ones.cloud();
    Field q(c.size());
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& p = c.positions[static_cast<std::size_t>(i)];
      q[i] = p[0] * p[0] + p[0] * p[1] + 2 * p[1] * p[1];  // Laplacian 6
    }
    const Eigen::MatrixXd Aq = constant.apply(OperatorKind::DivAGrad, q);
    const Stencil& own_rows = own.stencil(OperatorKind::DivAGrad);
    const Stencil& taken = smooth.stencil(OperatorKind::DivAGrad);
    for (Index i = 0; i < c.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      EXPECT_NEAR(taken.residual[si], own_rows.residual[si], 1e-9) << "row " << i;  // one optimum value
      if (c.tags[si] != Tag::Interior || lap.residual[si] > 1e-10) continue;
      EXPECT_NEAR(Aq(i, 0), 2.5 * 6, 1e-5) << "row " << i;
    }
  }
  // set_coefficient rebuilds div(a grad) alone, on the Laplacian's volumes: a = 2, twice its rows
  // (bit for bit: products with powers of two are exact); the Laplacian is untouched.
  const Stencil lap = ones.stencil(OperatorKind::Laplacian);
  ones.set_coefficient(Field::Constant(ones.cloud().size(), 2.0));
  EXPECT_EQ(ones.stats().borrowed_rows, ones.cloud().size());
  expect_same_stencil(ones.stencil(OperatorKind::Laplacian), lap);
  Stencil doubled = lap;
  for (Real& v : doubled.values[0]) v *= 2;
  expect_same_stencil(ones.stencil(OperatorKind::DivAGrad), doubled);
}

// Second order on moving particles: div(a grad u) for a = 1 + sin(2 pi x) cos(2 pi y) / 2 and
// u = sin(2 pi x) cos(2 pi y) on a periodic perturbed cloud advected three steps, a updated with
// the places; interior max error over n = 16, 32, 64.
TEST(MovingOperators, VrsphDivAGradIsSecondOrderOnMovingParticles) {
  const auto a_at = [](const Vec3& p) { return 1 + 0.5 * std::sin(2 * std::numbers::pi * p[0]) * std::cos(2 * std::numbers::pi * p[1]); };
  std::vector<Real> errors;
  for (const int n : {16, 32, 64}) {
    const StudyCloud sc = operators_cloud(2, "x,y", n, 4);
    OperatorsOptions o;
    o.operators = {OperatorKind::Laplacian, OperatorKind::DivAGrad};
    Field a(sc.cloud.size());
    for (Index i = 0; i < a.size(); ++i) a[i] = a_at(sc.cloud.positions[static_cast<std::size_t>(i)]);
    o.coefficient = a;
    Operators ops(sc.cloud, o);
    for (int step = 0; step < 3; ++step) {
      const std::vector<Vec3> x = advect(ops.cloud(), 0.1 / n);
      for (Index i = 0; i < a.size(); ++i) a[i] = a_at(x[static_cast<std::size_t>(i)]);
      ops.update(x, a);
    }
    const Real k = 2 * std::numbers::pi;
    const PointCloud& c = ops.cloud();
    Field u(c.size()), exact(c.size());
    for (Index i = 0; i < c.size(); ++i) {
      const Vec3& p = c.positions[static_cast<std::size_t>(i)];
      const Real s = std::sin(k * p[0]), co = std::cos(k * p[0]), sy = std::sin(k * p[1]), cy = std::cos(k * p[1]);
      u[i] = s * cy;
      // grad a . grad u + a lap u, grad a = grad u / 2
      exact[i] = 0.5 * k * k * (co * cy * co * cy + s * sy * s * sy) + a_at(p) * (-2 * k * k * u[i]);
    }
    errors.push_back((ops.apply(OperatorKind::DivAGrad, u).col(0) - exact).cwiseAbs().maxCoeff());
  }
  const Real order1 = std::log2(errors[0] / errors[1]), order2 = std::log2(errors[1] / errors[2]);
  std::cout << "div(a grad) on moving particles: errors " << errors[0] << ", " << errors[1] << ", " << errors[2]
            << ", orders " << order1 << ", " << order2 << "\n";
  EXPECT_GT(order1, 1.6);
  EXPECT_GT(order2, 1.6);
  EXPECT_LT(order2, 2.4);
}

// The coefficient's bad input: refused before anything changes.
TEST(MovingOperators, DivAGradCoefficientRefusalsLeaveTheOperatorsAsTheyWere) {
  const StudyCloud sc = operators_cloud(2);
  OperatorsOptions o;
  o.operators = {OperatorKind::DivAGrad};
  EXPECT_THROW_MSG(Operators(sc.cloud, o), ConfigError, "needs the coefficient");
  o.coefficient = smooth_coefficient(sc.cloud);
  o.coefficient[7] = 0;
  EXPECT_THROW_MSG(Operators(sc.cloud, o), InputError, "at particle 7");
  o.coefficient = smooth_coefficient(sc.cloud);
  Operators ops(sc.cloud, o);
  OperatorsOptions plain;
  plain.coefficient = o.coefficient;
  EXPECT_THROW_MSG(Operators(sc.cloud, plain), ConfigError, "not among the operators");
  Operators laplacian(sc.cloud, {});
  EXPECT_THROW_MSG(laplacian.set_coefficient(o.coefficient), ConfigError, "not among the operators");
  EXPECT_THROW_MSG(laplacian.update(laplacian.cloud().positions, o.coefficient), ConfigError, "not kept");

  ops.update(advect(ops.cloud(), 0.01));
  const Stencil before = ops.stencil(OperatorKind::DivAGrad);
  const Field a_before = ops.coefficient();
  Field bad = smooth_coefficient(sc.cloud);
  bad[3] = std::nan("");
  EXPECT_THROW_MSG(ops.set_coefficient(bad), InputError, "at particle 3");
  bad[3] = -1;
  EXPECT_THROW_MSG(ops.update(advect(ops.cloud(), 0.01), bad), InputError, "positive and finite");
  EXPECT_THROW_MSG(ops.set_coefficient(Field::Ones(5)), InputError, "5 values for");
  std::vector<Vec3> x = advect(ops.cloud(), 0.01);
  x[10][0] = std::nan("");  // a bad position with a good coefficient: neither is taken
  EXPECT_THROW(ops.update(x, Field::Constant(a_before.size(), 3.0)), InputError);
  x = advect(ops.cloud(), 0.01);
  x[10] = x[11];  // a duplicate, found in the neighbour phase
  EXPECT_THROW(ops.update(x, Field::Constant(a_before.size(), 3.0)), InputError);
  EXPECT_EQ(ops.coefficient(), a_before);
  expect_same_stencil(ops.stencil(OperatorKind::DivAGrad), before);
  // A good one: the stencil rebuilt now on the same places, twice the coefficient twice the rows.
  ops.set_coefficient(2 * a_before);
  const Stencil& twice = ops.stencil(OperatorKind::DivAGrad);
  for (std::size_t k = 0; k < twice.values[0].size(); ++k) EXPECT_NEAR(twice.values[0][k], 2 * before.values[0][k], 1e-9 * std::abs(before.values[0][k]) + 1e-300);
}

namespace {
// A superset of the pairs within `radius` (a caller's cell or Verlet list), in CSR form.
struct Candidates {
  std::vector<Index> offsets, indices;
  std::vector<Real> distances;
  UserNeighbours view(bool with_distances) const {
    UserNeighbours u;
    u.offsets = offsets;
    u.indices = indices;
    if (with_distances) u.distances = distances;
    return u;
  }
};
Candidates candidates_within(const PointCloud& c, Real radius) {
  SearchParams sp;
  sp.radius = radius;
  sp.wrap_periodic = true;
  const NeighbourList nl = find_neighbours(c, sp);
  Candidates out;
  out.offsets.assign(nl.offsets.begin(), nl.offsets.end());
  out.indices.assign(nl.indices.begin(), nl.indices.end());
  out.distances.assign(nl.distances.begin(), nl.distances.end());
  // Rows in another order than the library's: reversed.
  for (std::size_t i = 0; i < static_cast<std::size_t>(c.size()); ++i) {
    const auto b = static_cast<std::ptrdiff_t>(out.offsets[i]), e = static_cast<std::ptrdiff_t>(out.offsets[i + 1]);
    std::reverse(out.indices.begin() + b, out.indices.begin() + e);
    std::reverse(out.distances.begin() + b, out.distances.begin() + e);
  }
  return out;
}
}  // namespace

// The caller's candidate pairs (its own cell or Verlet list, wider than the support) instead of
// the operators' Verlet list: the same list after filtering, so (cold) the same stencils bit for
// bit, on the box and on a periodic one; plain updates after them still use the Verlet list.
TEST(MovingOperators, TheCallersCandidatePairsGiveTheStencilsOfTheVerletList) {
  for (const std::string periodic : {"", "x,y"}) {
    const StudyCloud sc = operators_cloud(2, periodic);
    OperatorsOptions o;
    o.warm_start = false;
    o.operators = {OperatorKind::Laplacian, OperatorKind::Gradient};
    Operators own(sc.cloud, o), given(sc.cloud, o);
    for (int step = 0; step < 4; ++step) {
      const std::vector<Vec3> x = advect(own.cloud(), 0.01);
      own.update(x);
      if (step == 3) {
        given.update(x);  // back to the Verlet list
      } else {
        PointCloud moved = own.cloud();
        const Candidates c = candidates_within(moved, 1.3 * own.radius());
        const UserNeighbours u = c.view(step == 1);
        given.update(x, UpdateWith{nullptr, &u});
        EXPECT_FALSE(given.stats().searched);
      }
      EXPECT_EQ(given.neighbours().offsets, own.neighbours().offsets);
      EXPECT_EQ(given.neighbours().indices, own.neighbours().indices);
      EXPECT_EQ(given.neighbours().distances, own.neighbours().distances);
      EXPECT_EQ(given.neighbours().shifts, own.neighbours().shifts);
      for (const OperatorKind k : {OperatorKind::Laplacian, OperatorKind::Gradient})
        expect_same_stencil(given.stencil(k), own.stencil(k));
    }
  }
}

// Candidate lists refused with the row named; the operators stay as they were.
TEST(MovingOperators, BadCandidatePairsAreRefusedAndChangeNothing) {
  const StudyCloud sc = operators_cloud(2);
  Operators ops(sc.cloud, {});
  ops.update(advect(ops.cloud(), 0.01));
  const Stencil before = ops.stencil(OperatorKind::Laplacian);
  const std::vector<Real> distances_before(ops.neighbours().distances.begin(), ops.neighbours().distances.end());
  std::vector<Vec3> x = advect(ops.cloud(), 0.01);
  PointCloud moved = ops.cloud();
  moved.positions = x;
  Candidates c = candidates_within(moved, 1.2 * ops.radius());
  // One direction of a close pair dropped: row 40's first candidate within the radius.
  const auto row = static_cast<std::size_t>(40);
  auto drop = static_cast<std::size_t>(c.offsets[row]);  // its first candidate within the radius
  while (c.distances[drop] >= ops.radius()) ++drop;
  Candidates one_sided = c;
  one_sided.indices.erase(one_sided.indices.begin() + static_cast<std::ptrdiff_t>(drop));
  one_sided.distances.erase(one_sided.distances.begin() + static_cast<std::ptrdiff_t>(drop));
  for (std::size_t i = row + 1; i < one_sided.offsets.size(); ++i) --one_sided.offsets[i];
  UserNeighbours u = one_sided.view(false);
  EXPECT_THROW_MSG(ops.update(x, UpdateWith{nullptr, &u}), InputError, "one-sided");
  Candidates out_of_range = c;
  out_of_range.indices[5] = ops.cloud().size();
  u = out_of_range.view(false);
  EXPECT_THROW_MSG(ops.update(x, UpdateWith{nullptr, &u}), InputError, "outside 0..");
  Candidates wrong_distance = c;
  wrong_distance.distances[drop] *= 0.5;
  u = wrong_distance.view(true);
  EXPECT_THROW_MSG(ops.update(x, UpdateWith{nullptr, &u}), InputError, "but the positions give");
  std::vector<Vec3> twin = x;
  twin[40] = twin[41];
  u = c.view(false);  // 40 and 41 list each other
  EXPECT_THROW_MSG(ops.update(twin, UpdateWith{nullptr, &u}), InputError, "duplicate particles 40 and 41");
  expect_same_stencil(ops.stencil(OperatorKind::Laplacian), before);
  EXPECT_EQ(std::vector<Real>(ops.neighbours().distances.begin(), ops.neighbours().distances.end()), distances_before);
  EXPECT_EQ(ops.stats().updates, 1);
}
