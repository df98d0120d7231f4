// SPDX-License-Identifier: BSD-3-Clause
#include <limits>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/algebra.hpp>
#include <vrsph/stencil/apply.hpp>
#include "test_util.hpp"

using namespace vrsph;

namespace {
struct Fixture {
  PointCloud cloud = [] {
    PointCloud c = vertex_lattice(Domain::unit_box(2), 8);
    perturb(c, {0.3, 5, false});
    return c;
  }();
  NeighbourList nl = [this] {
    SearchParams p;
    p.radius = 2.5 * cloud.spacing;
    return find_neighbours(cloud, p);
  }();
};
}  // namespace

TEST(Stencil, PatternHasSortedColumnsAndTheDiagonal) {
  Fixture f;
  const Stencil s = make_stencil_pattern(f.nl, OperatorKind::Gradient, 2, "test");
  ASSERT_EQ(s.rows(), f.cloud.size());
  EXPECT_EQ(s.nnz(), f.nl.total() + f.cloud.size());
  EXPECT_EQ(s.components(), 2);
  for (Index i = 0; i < s.rows(); ++i) {
    EXPECT_EQ(s.col[static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])], i);
    for (Index k = s.row_begin(i) + 1; k < s.row_end(i); ++k)
      EXPECT_LT(s.col[static_cast<std::size_t>(k) - 1], s.col[static_cast<std::size_t>(k)]);
    for (Index k = 0; k < f.nl.count(i); ++k)
      EXPECT_EQ(s.col[static_cast<std::size_t>(neighbour_slot(s, i, k))], f.nl.of(i)[static_cast<std::size_t>(k)]);
  }
}

TEST(Stencil, ApplyAgreesWithTheEigenView) {
  Fixture f;
  const auto m = builtin_methods().create("sph");
  const Stencil s = m->build({f.cloud, f.nl, KernelType::CubicSpline, f.cloud.spacing}, {OperatorKind::Gradient});
  Field u(f.cloud.size());
  for (Index i = 0; i < u.size(); ++i) u[i] = std::sin(3.0 * i);
  const Eigen::MatrixXd out = apply(s, u);
  for (int c = 0; c < 2; ++c) {
    const Field ref = as_eigen(s, c) * u;
    EXPECT_LT((ref - out.col(c)).cwiseAbs().maxCoeff(), 1e-12 * (1 + ref.cwiseAbs().maxCoeff()));
  }
}

TEST(Stencil, SizeMismatchesAreReported) {
  Fixture f;
  const Stencil s = make_stencil_pattern(f.nl, OperatorKind::Laplacian, 2, "test");
  EXPECT_THROW_MSG(apply(s, Field::Zero(3)), InputError, "field has 3 values but the stencil has");
  EXPECT_THROW_MSG(as_eigen(s, 1), InputError, "component 1 out of range");
  EXPECT_THROW_MSG(make_stencil_pattern(f.nl, OperatorKind::Dz, 2, "t"), ConfigError, "dz needs dimension 3");
}

// Pairs plus diagonals beyond a 32-bit index: refused with the true count (issue 31: the
// size used to wrap around to a negative number in the memory message). Only the offsets
// are needed; the check comes before any row is read.
TEST(Stencil, PatternsBeyondA32BitIndexAreRefusedByTheirSize) {
  NeighbourList nl;
  const Index big = std::numeric_limits<Index>::max() - 1;
  nl.offsets = {0, big, big, big};
  EXPECT_THROW_MSG(make_stencil_pattern(nl, OperatorKind::Laplacian, 2, "t"), ResourceError,
                   "would have 2147483649 entries (2147483646 neighbour pairs and 3 diagonals), more than the 2147483647");
}

TEST(Stencil, OperatorNamesRoundTrip) {
  for (const auto& t : operator_catalogue()) EXPECT_EQ(parse_operator(t.name), t.kind);
  EXPECT_EQ(parse_operator("second-derivative"), OperatorKind::Laplacian);
  EXPECT_EQ(parse_operator("first-derivative"), OperatorKind::Dx);
  EXPECT_THROW_MSG(parse_operator("jacobian"), ConfigError, "unknown operator 'jacobian'");
  EXPECT_EQ(parse_operator("hessian"), OperatorKind::Hessian);
  EXPECT_EQ(components(OperatorKind::Gradient, 3), 3);
  EXPECT_EQ(components(OperatorKind::Laplacian, 3), 1);
}

// Splicing: the marked rows from one stencil, the others from another, whatever their patterns
// (FPM's Laplacian over the neighbour list against RKPM's nested one over two rings), each row's
// per-row outputs with it, and applied it gives each source's result on its own rows.
TEST(Stencil, SplicedRowsComeFromTheirOwnStencilWithTheirOutputs) {
  Fixture f;
  const Discretisation disc{f.cloud, f.nl, KernelType::CubicSpline, f.cloud.spacing};
  const Stencil base = builtin_methods().create("fpm")->build(disc, {OperatorKind::Laplacian});
  const Stencil from = builtin_methods().create("rkpm1")->build(disc, {OperatorKind::Laplacian});  // two rings
  ASSERT_NE(base.nnz(), from.nnz());  // another pattern
  ASSERT_FALSE(base.condition.empty());
  std::vector<char> rows(static_cast<std::size_t>(f.cloud.size()), 0);
  for (std::size_t i = 0; i < rows.size(); i += 3) rows[i] = 1;
  Stencil out;
  splice_rows(base, from, rows, out);
  ASSERT_EQ(out.rows(), base.rows());
  Field u(f.cloud.size());
  for (Index i = 0; i < u.size(); ++i) u[i] = std::cos(0.7 * i);
  const Eigen::MatrixXd a = apply(out, u), b = apply(base, u), c = apply(from, u);
  for (Index i = 0; i < out.rows(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Stencil& src = rows[si] ? from : base;
    EXPECT_EQ(out.row_end(i) - out.row_begin(i), src.row_end(i) - src.row_begin(i));
    EXPECT_EQ(out.col[static_cast<std::size_t>(out.diag[si])], i);
    EXPECT_EQ(a(i, 0), rows[si] ? c(i, 0) : b(i, 0));  // bitwise: the same entries in the same order
    EXPECT_EQ(out.condition[si], src.condition.empty() ? 0.0 : src.condition[si]);
  }
  EXPECT_EQ(out.method, "fpm");
  Stencil no_outputs = from;  // an output only one stencil has: 0 in the other's rows
  no_outputs.condition.clear();
  splice_rows(base, no_outputs, rows, out);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(out.condition[i], rows[i] ? 0.0 : base.condition[i]);
  splice_rows(base, from, std::vector<char>(rows.size(), 0), out);  // nothing marked: base itself
  EXPECT_EQ(out.col, base.col);
  EXPECT_EQ(out.values, base.values);
  EXPECT_THROW_MSG(splice_rows(base, from, std::vector<char>(3, 1), out), InputError, "3 entries for");
  const Stencil gradient = builtin_methods().create("fpm")->build(disc, {OperatorKind::Gradient});
  EXPECT_THROW_MSG(splice_rows(base, gradient, rows, out), InputError, "cannot take rows of a gradient stencil");
}

namespace {
// The stencil as a dense matrix per component, and its right-hand-side weights.
std::vector<Eigen::MatrixXd> dense(const Stencil& s) {
  std::vector<Eigen::MatrixXd> out;
  for (int c = 0; c <= s.components(); ++c) {
    if (c == s.components() && s.rhs.empty()) break;
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(s.rows(), s.rows());
    const auto& v = c < s.components() ? s.values[static_cast<std::size_t>(c)] : s.rhs;
    for (Index i = 0; i < s.rows(); ++i)
      for (Index k = s.row_begin(i); k < s.row_end(i); ++k) m(i, s.col[static_cast<std::size_t>(k)]) = v[static_cast<std::size_t>(k)];
    out.push_back(m);
  }
  return out;
}

// A replacement of row i over the columns i + offsets (those inside the stencil), values from
// a formula, right-hand side too.
RowReplacement replacement(const Stencil& s, Index i, std::initializer_list<Index> offsets) {
  RowReplacement r;
  r.row = i;
  for (const Index o : offsets)
    if (i + o >= 0 && i + o < s.rows()) r.col.push_back(i + o);
  r.values.assign(static_cast<std::size_t>(s.components()), {});
  for (int c = 0; c < s.components(); ++c)
    for (const Index j : r.col) r.values[static_cast<std::size_t>(c)].push_back(100.0 * (c + 1) + j + 0.5 * i);
  for (const Index j : r.col) r.rhs.push_back(-1.0 * j - i);
  return r;
}
}  // namespace

TEST(Stencil, ReplacedRowsTakeTheirOwnPatternsWhetherShorterOrLongerAndTheRestStays) {
  Fixture f;
  Stencil base = make_stencil_pattern(f.nl, OperatorKind::Gradient, 2, "test");
  base.rhs.assign(base.col.size(), 0.0);
  for (std::size_t k = 0; k < base.col.size(); ++k) {
    base.values[0][k] = std::sin(1.0 + static_cast<double>(k));
    base.values[1][k] = std::cos(2.0 + static_cast<double>(k));
    base.rhs[k] = 0.25 * static_cast<double>(k);
  }
  const Index n = base.rows();
  std::vector<Index> every(static_cast<std::size_t>(n));
  for (Index j = 0; j < n; ++j) every[static_cast<std::size_t>(j)] = j;
  const auto full_row = [&](Index i) {
    RowReplacement r = replacement(base, i, {0});
    r.col = every;
    r.values.assign(2, std::vector<Real>(every.size(), 3.0));
    r.values[1][static_cast<std::size_t>(i)] = -7;
    r.rhs.assign(every.size(), 0.5);
    return r;
  };
  // Shorter rows only (in place); shorter and longer within the spare capacity (blocks move
  // left and right); longer than the capacity holds (fresh arrays); first and last rows.
  const std::vector<std::vector<RowReplacement>> cases{
      {replacement(base, 0, {0, 1}), replacement(base, 40, {-1, 0}), replacement(base, n - 1, {0})},
      {replacement(base, 3, {0}), full_row(20), replacement(base, 50, {-9, -1, 0, 1, 9})},
      {full_row(0), replacement(base, 10, {0}), full_row(n - 2), full_row(n - 1)},
  };
  for (std::size_t t = 0; t < cases.size(); ++t) {
    SCOPED_TRACE(t);
    Stencil s = base;
    s.col.reserve(base.col.size() + base.col.size() / 16);
    auto expected = dense(base);
    for (const RowReplacement& r : cases[t])
      for (std::size_t c = 0; c < expected.size(); ++c) {
        expected[c].row(r.row).setZero();
        const auto& v = c < 2 ? r.values[c] : r.rhs;
        for (std::size_t k = 0; k < r.col.size(); ++k) expected[c](r.row, r.col[k]) = v[k];
      }
    replace_rows(s, cases[t]);
    const auto got = dense(s);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t c = 0; c < got.size(); ++c) EXPECT_EQ((got[c] - expected[c]).cwiseAbs().maxCoeff(), 0) << c;
    ASSERT_EQ(s.col.size(), static_cast<std::size_t>(s.nnz()));
    ASSERT_EQ(s.rhs.size(), s.col.size());
    for (Index i = 0; i < n; ++i) {
      EXPECT_EQ(s.col[static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])], i) << i;
      for (Index k = s.row_begin(i) + 1; k < s.row_end(i); ++k)
        EXPECT_LT(s.col[static_cast<std::size_t>(k) - 1], s.col[static_cast<std::size_t>(k)]) << i;
    }
  }
  // Malformed replacements are named, and leave the stencil as it was.
  Stencil s = base;
  RowReplacement unsorted = replacement(base, 5, {1, 0});
  EXPECT_THROW_MSG(replace_rows(s, std::vector<RowReplacement>{unsorted}), InputError, "must be sorted, distinct");
  EXPECT_THROW_MSG(replace_rows(s, std::vector<RowReplacement>{replacement(base, 5, {1})}), InputError,
                   "include the row itself");
  EXPECT_THROW_MSG(replace_rows(s, std::vector<RowReplacement>{replacement(base, 6, {0}), replacement(base, 5, {0})}),
                   InputError, "out of order");
  RowReplacement short_values = replacement(base, 5, {0, 1});
  short_values.values[1].pop_back();
  EXPECT_THROW_MSG(replace_rows(s, std::vector<RowReplacement>{short_values}), InputError, "values for 2 columns");
  EXPECT_EQ(s.col, base.col);
  EXPECT_EQ(s.values, base.values);
}
