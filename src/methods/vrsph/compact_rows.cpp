// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/methods/monomials.hpp>
#include <vrsph/methods/vrsph/compact_rows.hpp>
#include <vrsph/methods/vrsph/moments.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>
#include <vrsph/methods/vrsph/simplex.hpp>

namespace vrsph {

namespace {
constexpr Real kPolishBelow = 1e-6;   // residuals NNLS left that the polish is tried on,
constexpr Real kPolishAbove = 1e-13;  // above round-off (most rows: the polish would be a no-op)
constexpr int kPhase1PivotsPerSize = 1;  // phase 1's pivot limit over (rows + columns): least_truncation_row

// e^alpha with the powers of e's coordinates tabulated (pw[k][p] = e_k^p).
Real monomial(const std::array<std::array<Real, 8>, 3>& pw, const std::array<int, 3>& a) {
  return pw[0][static_cast<std::size_t>(a[0])] * pw[1][static_cast<std::size_t>(a[1])] * pw[2][static_cast<std::size_t>(a[2])];
}

// NNLS stops at a residual of ~1e-12 of the scaled system; the row's truncation error is
// that residual over h (the degree-1 rows), which at fine resolution is no longer below the
// O(h^3) it is meant to reach. The minimum-norm correction on the support (the non-zero
// columns) removes it when it keeps every volume positive (it always does for a residual this
// small, unless a volume is at round-off); the columns in [free_begin, free_end) (a signed
// average's μ) may take either sign. Returns the residual left.
Real polish(const std::vector<Real>& A, int R, std::size_t C, const std::vector<Real>& b, std::vector<Real>& x,
            std::size_t free_begin = 0, std::size_t free_end = 0) {
  const Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(A.data(), R, static_cast<Eigen::Index>(C));
  Eigen::Map<Eigen::VectorXd> xv(x.data(), static_cast<Eigen::Index>(C));
  const Eigen::Map<const Eigen::VectorXd> bv(b.data(), R);
  const Eigen::VectorXd r = bv - M * xv;
  std::vector<Eigen::Index> support;
  for (Eigen::Index j = 0; j < xv.size(); ++j)
    if (xv[j] != 0) support.push_back(j);
  Eigen::MatrixXd S(R, static_cast<Eigen::Index>(support.size()));
  for (std::size_t k = 0; k < support.size(); ++k) S.col(static_cast<Eigen::Index>(k)) = M.col(support[k]);
  const Eigen::VectorXd d = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(S).solve(r);
  bool positive = true;
  for (std::size_t k = 0; k < support.size(); ++k) {
    const auto j = static_cast<std::size_t>(support[k]);
    const bool free = j >= free_begin && j < free_end;
    positive = positive && (free || xv[support[k]] + d[static_cast<Eigen::Index>(k)] > 0);
  }
  if (positive && (S * d - r).norm() < r.norm())
    for (std::size_t k = 0; k < support.size(); ++k) xv[support[k]] += d[static_cast<Eigen::Index>(k)];
  return (bv - M * xv).norm();
}

// The operator rows of one degree as table look-ups: every monomial e^beta with |beta| <= degree
// is evaluated once per column (vals), and each moment row reads its own value and the terms
// of (a Δq + h ∇a·∇q) for q = e^alpha from it (a quarter of the compact rows' time went to
// recomputing those products per row and column). The terms sit in fixed arrays inside the
// row (at most one per axis): a vector per row cost a pointer chase per row and column.
struct OperatorTable {
  std::vector<std::array<int, 3>> all;  // every exponent with |beta| <= degree: vals[k] = e^all[k]
  struct Term {
    int axis = 0;
    Real coefficient = 0;
    int index = 0;  // into `all`
  };
  struct Row {
    int value = 0;                     // index of alpha in `all`
    int n_laplacian = 0, n_drift = 0;  // terms used below
    std::array<Term, 3> laplacian{};   // alpha_k (alpha_k - 1) e^(alpha - 2 e_k)
    std::array<Term, 3> drift{};       // alpha_k e^(alpha - e_k), times h (∂a/∂x_k)
  };
  std::vector<Row> rows;
};

OperatorTable operator_table(int dim, int degree, const std::vector<std::array<int, 3>>& mo) {
  OperatorTable t;
  for (int deg = 0; deg <= degree; ++deg)
    for (int a0 = deg; a0 >= 0; --a0)
      for (int a1 = deg - a0; a1 >= 0; --a1) {
        const std::array<int, 3> a{a0, a1, deg - a0 - a1};
        if ((dim < 2 && a[1]) || (dim < 3 && a[2])) continue;
        t.all.push_back(a);
      }
  const auto index = [&](const std::array<int, 3>& a) {
    return static_cast<int>(std::find(t.all.begin(), t.all.end(), a) - t.all.begin());
  };
  for (const auto& al : mo) {
    OperatorTable::Row r;
    r.value = index(al);
    for (int k = 0; k < dim; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      if (al[uk] >= 2) {
        std::array<int, 3> b = al;
        b[uk] -= 2;
        r.laplacian[static_cast<std::size_t>(r.n_laplacian++)] = {k, static_cast<Real>(al[uk] * (al[uk] - 1)), index(b)};
      }
      if (al[uk] >= 1) {
        std::array<int, 3> b = al;
        b[uk] -= 1;
        r.drift[static_cast<std::size_t>(r.n_drift++)] = {k, static_cast<Real>(al[uk]), index(b)};
      }
    }
    t.rows.push_back(r);
  }
  return t;
}

// Column scales (r_min / r_j)^2.5: NNLS's multiplier test then prefers near neighbours. Not the
// square of the point rows: with it, every w column's multiplier at the second step is
// s_j |e_j|^2 c = (r_min / h)^2 c, the same for all neighbours, so round-off chose the second
// column and with it the whole path — the weights of 1403 of 1521 rows changed when the
// coordinates were scaled by 1 + 1e-13, and the error by a factor 2. The power 2.5 breaks that
// tie gently (r_j^-0.5); 3 and 4 favoured the nearest so strongly that the wall rows of mixed
// problems fell to first order (tests/convergence/test_vrsph_walls.cpp).
void column_scales(std::span<const Real> distances, std::vector<Real>& scale) {
  Real r_min = std::numeric_limits<Real>::infinity();
  for (const Real d : distances) r_min = std::min(r_min, d);
  scale.resize(distances.size());
  for (std::size_t j = 0; j < distances.size(); ++j) {
    const Real q = r_min / distances[j];
    scale[j] = q * q * std::sqrt(q);
  }
}
// Multipliers within this relative width of the largest tie (the first such column enters):
// far above the round-off of a change of unit, far below the gaps between genuinely different
// columns; on a lattice symmetric neighbours tie exactly and their order decides.
constexpr Real kTieTolerance = 1e-10;

void tabulate(const Vec3& e, int degree, std::array<std::array<Real, 8>, 3>& pw) {
  for (int k = 0; k < 3; ++k) {
    pw[static_cast<std::size_t>(k)][0] = 1;
    for (int p = 1; p <= degree; ++p)
      pw[static_cast<std::size_t>(k)][static_cast<std::size_t>(p)] = pw[static_cast<std::size_t>(k)][static_cast<std::size_t>(p - 1)] * e[k];
  }
}
}  // namespace

namespace {
// The monomials of each degree and their operator tables, built once per call.
struct MonomialTables {
  std::vector<std::vector<std::array<int, 3>>> mono;
  std::vector<OperatorTable> table;
  /// Per degree d: the rows of table[d] whose monomial has degree exactly d, and α!.
  std::vector<std::vector<std::pair<std::size_t, Real>>> top;
  MonomialTables(int dim, int min_degree, int degree)
      : mono(static_cast<std::size_t>(degree) + 1), table(static_cast<std::size_t>(degree) + 1),
        top(static_cast<std::size_t>(degree) + 1) {
    for (int d = min_degree; d <= degree; ++d) {
      const auto ud = static_cast<std::size_t>(d);
      mono[ud] = monomial_exponents(dim, d);
      table[ud] = operator_table(dim, d, mono[ud]);
      for (std::size_t r = 0; r < mono[ud].size(); ++r) {
        const auto& alpha = mono[ud][r];
        if (alpha[0] + alpha[1] + alpha[2] != d) continue;
        Real factorial = 1;
        for (const int e : alpha)
          for (int q = 2; q <= e; ++q) factorial *= q;
        top[ud].emplace_back(r, factorial);
      }
    }
  }
};

// One thread's compact rows: per-thread workspaces, and for each wanted particle the highest
// degree that admits w, μ >= 0 (or a signed average, CompactRowOptions::signed_average). Rows:
// one per monomial q = e^alpha of e = (x - x_i)/h, scaled by h^-|alpha| (with ŵ = w h^2 every
// entry is O(1)):
//   Σ_j ŵ_j q(e_j) - Σ_k μ_k (a_k Δq + h ∇a_k·∇q)(e_k) = 0;  then Σ_k μ_k = 1.
class CompactRowSolver {
 public:
  CompactRowSolver(const Discretisation& disc, const Field* a, const Eigen::MatrixXd* grad_a, const MonomialTables& t,
                   const CompactRowOptions& options, Real wave_number, const CompactWalls& walls, Index max_count,
                   Stencil& target, CompactRows& out)
      : disc_(disc), a_(a), grad_a_(grad_a), t_(t), options_(options), wave_number_(wave_number), walls_(walls),
        target_(target), out_(out),
        solver_(static_cast<int>(t.mono[static_cast<std::size_t>(options.degree)].size()) + 1, 2 * static_cast<int>(max_count) + 2),
        lp_(static_cast<int>(t.mono[static_cast<std::size_t>(options.degree)].size()) + 1, 2 * static_cast<int>(max_count) + 2) {}

  // Row i's positive row of the top degree over its own support (first the inner neighbours,
  // then all), accepted where found. Where none is found and `defer` is set, the row is left
  // for solve_wide and lower_degrees (true returned: the caller tries the wider support first,
  // and the lower degrees over this support only where that fails); else the lower degrees
  // here (false returned).
  bool solve(Index i, bool defer) {
    const NeighbourList& nl = disc_.neighbours;
    wide_ = nullptr;
    own_support(i);
    const auto distances = nl.distances_of(i);
    // First the inner neighbours alone, at the top degree: the most compact positive row
    // (on a lattice the Mehrstellen-type row of the nearest two shells, 22 times more accurate
    // on Example 5 than the row NNLS picks from the whole support; on disordered clouds as
    // accurate, and a smaller system). Where they admit none, the whole support.
    columns_.clear();
    if (options_.inner_support < 1) {
      const Real r = options_.inner_support * nl.radius(i);
      for (std::size_t j = 0; j < distances.size(); ++j)
        if (distances[j] <= r) columns_.push_back(j);
      if (columns_.size() < distances.size() && solve_degree(i, options_.degree, false)) {
        accept(i, options_.degree, false);
        return false;
      }
    }
    all_columns(distances.size());
    if (solve_degree(i, options_.degree, false)) {
      accept(i, options_.degree, false);
      return false;
    }
    if (defer) return true;
    lower_degrees(i);
    return false;
  }

  // Row i over its own support below the top degree (solve() found no positive row of the
  // top degree there, and the wider support, where tried, none either).
  // The highest degree that admits w, μ >= 0 (next to a wall often only 3: still a
  // positive row with the O(h) part of the truncation moved into the average of f). With
  // signed averages the signed row of the first degree without a positive one competes with
  // that positive row on its estimated truncation: a row one degree short with a positive
  // average is the worse at fine resolution (the error spikes of the few rows by the walls
  // and at voids of a disordered cloud set the max-norm error there), a signed row whose μ
  // is large and cancelling is the worse at coarse resolution. Not at walls (flux=balance
  // rows): a wall row's error is not confined to its particle, and on mixed problems signed
  // wall rows were 7-16 times more accurate at n = 128 but up to 4 times less at n = 16.
  void lower_degrees(Index i) {
    wide_ = nullptr;
    own_support(i);
    all_columns(static_cast<std::size_t>(disc_.neighbours.count(i)));
    lower_degree_row(i, false);
  }

  // The same over the wider support that solve_wide(i, row) just tried (CompactRowOptions::
  // wide_lower_degrees); true, and the row in `row`, where it admits one (positive or signed,
  // held to the test of a Laplacian-type row as the wider support's rows are).
  bool wide_lower_degrees(Index i, RowReplacement& row) {
    if (wide_row_ != i) return false;  // solve_wide found no wider support for row i
    const auto si = static_cast<std::size_t>(i);
    candidates_ = wide_candidates_;
    column_scales(wide_distances_, scale_);
    all_columns(wide_candidates_.size());
    const Real residual_before = out_.residual[si];
    wide_ = &row;
    const bool found = lower_degree_row(i, true);
    if (!found) out_.residual[si] = residual_before;
    wide_ = nullptr;
    return found;
  }

 private:
  // The chain of lower_degrees over the current candidates and columns; true where a row was
  // accepted. `laplacian` also holds the positive rows to laplacian_type.
  bool lower_degree_row(Index i, bool laplacian) {
    bool have_signed = false;
    int signed_degree = 0;
    Real signed_error = 0, signed_residual = 0;
    for (int deg = options_.degree; deg >= options_.min_degree; --deg) {
      // (the top degree's positive row: none, solve() found)
      if (deg < options_.degree && solve_degree(i, deg, false) && (!laplacian || laplacian_type(i, columns_.size()))) {
        if (have_signed && !(truncation_estimate(i, deg) < signed_error)) break;
        accept(i, deg, false);
        return true;
      }
      if (options_.signed_average && !have_signed && !wall_row(i) && solve_degree(i, deg, true)) {
        have_signed = true;
        signed_degree = deg;
        signed_x_ = x_;
        signed_residual = residual_;
        signed_error = truncation_estimate(i, deg);
      }
    }
    if (!have_signed) return false;
    x_ = signed_x_;
    residual_ = signed_residual;
    accept(i, signed_degree, true);
    return true;
  }

  // Row i's own neighbours as its candidates (and their columns' scales).
  void own_support(Index i) {
    const NeighbourList& nl = disc_.neighbours;
    candidates_ = nl.of(i);
    column_scales(nl.distances_of(i), scale_);  // the w and μ columns of neighbour j, scaled back below
  }
  // Every candidate a column.
  void all_columns(std::size_t count) {
    columns_.resize(count);
    for (std::size_t j = 0; j < count; ++j) columns_[j] = j;
  }

  // The columns of particle p from one evaluation of its monomials: its w column at w_col
  // (q(e_p); none for the row's own particle) and its μ column at mu_col
  // (-(a Δq + h ∇a·∇q)(e_p), and 1 in the Σ μ = 1 row).
  void columns(Index i, Index p, int deg, std::size_t w_col, std::size_t mu_col, bool with_w, Real s) {
    const OperatorTable& ops = t_.table[static_cast<std::size_t>(deg)];
    const auto R = static_cast<std::size_t>(rows_);
    Vec3 ga;
    const Real ap = evaluate_at(i, p, deg, ga);
    for (std::size_t r = 0; r + 1 < R; ++r) {
      const OperatorTable::Row& row = ops.rows[r];
      if (with_w) A_[r * C_ + w_col] = s * vals_[static_cast<std::size_t>(row.value)];
      A_[r * C_ + mu_col] = -s * operator_value(row, ap, ga);
    }
    A_[(R - 1) * C_ + mu_col] = s;
  }

  // Particle p's monomials of e = (x_p - x_i)/h up to degree `deg` into vals_ (in the order of
  // that degree's table); returns a at p, and h ∇a at p in ga (zero without grad_a_).
  Real evaluate_at(Index i, Index p, int deg, Vec3& ga) {
    const OperatorTable& ops = t_.table[static_cast<std::size_t>(deg)];
    const PointCloud& cloud = disc_.cloud;
    const Vec3 e = (cloud.positions[static_cast<std::size_t>(p)] - cloud.positions[static_cast<std::size_t>(i)]) / h_;
    tabulate(e, deg, pw_);
    vals_.resize(ops.all.size());
    for (std::size_t k = 0; k < ops.all.size(); ++k) vals_[k] = monomial(pw_, ops.all[k]);
    ga = Vec3::Zero();
    if (grad_a_)
      for (int k = 0; k < cloud.dim; ++k) ga[k] = h_ * (*grad_a_)(p, k);
    return a_ ? (*a_)[p] : 1.0;
  }

  // (a Δq + h ∇a·∇q) at the particle whose monomials vals_ holds, for q = e^α of `row` (ga: h ∇a
  // there; read only with grad_a_).
  Real operator_value(const OperatorTable::Row& row, Real ap, const Vec3& ga) const {
    Real lap = 0, drift = 0;
    for (int t = 0; t < row.n_laplacian; ++t) {
      const auto& term = row.laplacian[static_cast<std::size_t>(t)];
      lap += term.coefficient * vals_[static_cast<std::size_t>(term.index)];
    }
    if (grad_a_)
      for (int t = 0; t < row.n_drift; ++t) {
        const auto& term = row.drift[static_cast<std::size_t>(t)];
        drift += ga[term.axis] * term.coefficient * vals_[static_cast<std::size_t>(term.index)];
      }
    return ap * lap + drift;
  }

  // ĉ = c h times a_i n·∇q(0): only the degree-1 monomials q = e_k have ∇q(0) != 0.
  void wall_column(Index i, int deg, std::size_t col) {
    const auto& mo = t_.mono[static_cast<std::size_t>(deg)];
    for (std::size_t r = 0; r < static_cast<std::size_t>(rows_); ++r) {
      Real entry = 0;  // (every row is written: A is not zero-filled)
      if (r < mo.size() && mo[r][0] + mo[r][1] + mo[r][2] == 1)
        for (int k = 0; k < disc_.cloud.dim; ++k)
          if (mo[r][static_cast<std::size_t>(k)] == 1) entry = walls_.conormal[static_cast<std::size_t>(i)][k];
      A_[r * C_ + col] = entry;
    }
  }

  bool wall_row(Index i) const { return !walls_.rows.empty() && walls_.rows[static_cast<std::size_t>(i)]; }

  // The linear program's costs for the system build_system(i, deg) made: per column the bound
  // Σ_|α|=deg+1 |entry of that column in the row of e^α| / α! on its share of the row's
  // truncation at the next degree (w_j: |e_j^α|; μ_k: |a_k Δe^α + h ∇a_k·∇e^α| at e_k; μ_ii
  // and the wall flux: 0 from degree 3 on), times the column's scale.
  void truncation_costs(Index i, int deg) {
    const int m = deg + 1;
    const OperatorTable& ops = t_.table[static_cast<std::size_t>(m)];
    const auto& top = t_.top[static_cast<std::size_t>(m)];
    const std::size_t cnt = columns_.size();
    cost_.assign(C_, 0.0);
    for (std::size_t k = 0; k < cnt; ++k) {
      Vec3 ga;
      const Real ap = evaluate_at(i, candidates_[columns_[k]], m, ga);
      Real cw = 0, cmu = 0;
      for (const auto& [r, factorial] : top) {
        const OperatorTable::Row& row = ops.rows[r];
        cw += std::abs(vals_[static_cast<std::size_t>(row.value)]) / factorial;
        cmu += std::abs(operator_value(row, ap, ga)) / factorial;
      }
      const Real s = scale_[columns_[k]];
      cost_[k] = s * cw;
      cost_[cnt + k] = s * cmu;
    }
  }

  // Row i's system of degree `deg` over columns_ into A_ (row-major, rows_ x C_) and b_:
  // w, μ of the neighbours, μ_ii, the wall flux.
  void build_system(Index i, int deg) {
    const auto nbr = candidates_;
    const std::size_t cnt = columns_.size();
    const bool wall = wall_row(i);
    C_ = 2 * cnt + 1 + (wall ? 1 : 0);
    h_ = disc_.neighbours.radius(i);
    rows_ = static_cast<int>(t_.mono[static_cast<std::size_t>(deg)].size()) + 1;
    const auto R = static_cast<std::size_t>(rows_);
    // Every entry is written below except the Σ μ = 1 row's w columns and the wall column.
    A_.resize(R * C_);
    std::fill_n(A_.begin() + static_cast<std::ptrdiff_t>((R - 1) * C_), cnt, 0.0);
    b_.assign(R, 0.0);
    b_[R - 1] = 1;
    for (std::size_t k = 0; k < cnt; ++k) columns(i, nbr[columns_[k]], deg, k, cnt + k, true, scale_[columns_[k]]);
    columns(i, i, deg, 0, 2 * cnt, false, 1.0);
    if (wall) wall_column(i, deg, 2 * cnt + 1);
  }

  // True when row i admits degree `deg` over columns_ (w >= 0, the wall flux >= 0, and μ >= 0
  // or, signed_mu, of either sign); the solution in x_.
  bool solve_degree(Index i, int deg, bool signed_mu) {
    const auto si = static_cast<std::size_t>(i);
    build_system(i, deg);
    const std::size_t cnt = columns_.size();
    NnlsOptions options;
    options.tie_tolerance = kTieTolerance;
    NnlsResult r;
    if (!signed_mu) {
      x_.assign(C_, 0.0);
      if (!(options_.least_truncation && least_truncation_row(i, deg, r))) {
        // Where the program proved that no x >= 0 comes within the tolerance, the NNLS would
        // only confirm it (degree 6, n = 100: 13 663 such calls, not one of which found a
        // row, a fifth of the stencil time): the proven bound is the row's residual instead.
        if (options_.least_truncation && infeasible_bound_ > options_.tolerance) {
          record_residual(si, deg, infeasible_bound_);
          return false;
        }
        r = solver_.solve(A_.data(), rows_, static_cast<int>(C_), b_.data(), x_.data(), options, MatrixOrder::RowMajor);
      }
    } else {
      r = solve_signed(cnt, options);
    }
    // NNLS may stop at a residual somewhat above the tolerance (its multiplier test is
    // relative to ||A||): the polish below finishes such near-exact rows. A signed row's
    // residual is mostly the penalty's (of order κ² μ-): always polished.
    const std::size_t free_begin = signed_mu ? cnt : 0, free_end = signed_mu ? 2 * cnt + 1 : 0;
    Real res = r.residual > kPolishAbove && (signed_mu || r.residual <= kPolishBelow)
                   ? polish(A_, rows_, C_, b_, x_, free_begin, free_end)
                   : r.residual;
    record_residual(si, deg, res);
    if (!(r.status == NnlsStatus::Converged && res <= options_.tolerance)) return false;
    if (signed_mu && !laplacian_type(i, cnt)) return false;
    if (!signed_mu && lp_stopped_) res = least_truncation_from_nnls(res);
    residual_ = res;
    return true;
  }

  // An attempt's residual: the top degree's always, a lower degree's where it is smaller.
  void record_residual(std::size_t si, int deg, Real res) {
    if (deg == options_.degree || res < out_.residual[si]) out_.residual[si] = res;
  }

  // Phase 1 of the program stopped at its pivot limit and the NNLS found a positive row (x_):
  // the least-truncation row from there (phase 2 alone, from the NNLS's vertex), where it
  // meets the tolerance as well; else the NNLS's row stays. Returns the kept row's residual.
  Real least_truncation_from_nnls(Real nnls_residual) {
    start_ = x_;
    const LpResult lp = lp_.solve_from(A_.data(), rows_, static_cast<int>(C_), b_.data(), cost_.data(), start_.data(), x_.data());
    Real res = lp.status == LpStatus::Optimal ? residual() : std::numeric_limits<Real>::infinity();
    if (res > kPolishAbove && res <= kPolishBelow) res = polish(A_, rows_, C_, b_, x_);
    if (res <= options_.tolerance) return res;
    x_ = start_;
    return nnls_residual;
  }

  // The positive row of degree `deg` (system in A_, b_) whose truncation bound is least, by
  // the linear program; false where it finds none (infeasible, the iteration limit, or a vertex
  // the tableau's round-off left further from the conditions than the polish repairs: the NNLS
  // then decides, so a row is admitted or refused as without this option), with x_ zero.
  bool least_truncation_row(Index i, int deg, NnlsResult& r) {
    truncation_costs(i, deg);
    LpOptions o;
    // Phase 1 on these degenerate programs (every row homogeneous but Σ μ = 1) mostly ends
    // within m + n pivots, but on some (3D degree 6: 84 rows, a third of its rows' programs)
    // it wanders among degenerate vertices for thousands; past m + n the NNLS decides
    // feasibility instead, and phase 2 goes on from its row (least_truncation_from_nnls).
    // (The NNLS first for every program, phase 1 skipped, was 1.4-1.5 times slower.)
    o.phase1_iterations = kPhase1PivotsPerSize * (rows_ + static_cast<int>(C_));
    const LpResult lp = lp_.solve(A_.data(), rows_, static_cast<int>(C_), b_.data(), cost_.data(), x_.data(), o);
    infeasible_bound_ = lp.status == LpStatus::Infeasible ? lp.residual_bound : 0;
    lp_stopped_ = lp.status == LpStatus::IterationLimit;
    const Real res = lp.status == LpStatus::Optimal ? residual() : std::numeric_limits<Real>::infinity();
    if (!(res <= kPolishBelow)) {
      std::fill(x_.begin(), x_.end(), 0.0);
      return false;
    }
    r.status = NnlsStatus::Converged;
    r.iterations = lp.iterations;
    r.passive = lp.positive;
    r.residual = res;
    return true;
  }

  // A signed row must still be a Laplacian-type row: its average of the operator,
  // Σ_k μ_k a_k, within a factor of a_i (it is a_i (1 + O(h)) for a smooth a; a positive μ keeps
  // it between the stencil's smallest and largest a), and its second moment Σ_j ŵ_j |e_j|²
  // (2 d a_i for a smooth a) at least half of that. Where a varies by orders of magnitude (a
  // channelised medium) signed weights can cancel the operator out and leave a row without a
  // diagonal (w = 0, the row reads 0 = Σ μ f): such rows keep the point form.
  bool laplacian_type(Index i, std::size_t cnt) const {
    const auto nbr = candidates_;
    const PointCloud& cloud = disc_.cloud;
    const Real ai = a_ ? (*a_)[i] : 1.0;
    Real mean = x_[2 * cnt] * ai, second = 0;
    for (std::size_t k = 0; k < cnt; ++k) {
      const Index j = nbr[columns_[k]];
      const Real s = scale_[columns_[k]];
      mean += x_[cnt + k] * s * (a_ ? (*a_)[j] : 1.0);
      second += x_[k] * s * (cloud.positions[static_cast<std::size_t>(j)] - cloud.positions[static_cast<std::size_t>(i)]).squaredNorm();
    }
    second /= h_ * h_;
    return mean >= 0.5 * ai && mean <= 1.5 * ai && second >= cloud.dim * ai;
  }

  // w >= 0 and μ = μ+ - μ- (the columns of μ- appended, negated) with κ ||μ-|| added to the
  // fit: an NNLS on [A -A_μ; 0 κI] that takes negative weights only where the fit needs them,
  // and small ones (the signed volumes of boundary=signed do the same). x_ gets μ+ - μ-; the
  // residual returned is that of the original system (the penalty's share left to polish).
  NnlsResult solve_signed(std::size_t cnt, const NnlsOptions& options) {
    const auto R = static_cast<std::size_t>(rows_), nm = cnt + 1, C2 = C_ + nm, R2 = R + nm;
    M_.assign(R2 * C2, 0.0);
    c_.assign(R2, 0.0);
    for (std::size_t r = 0; r < R; ++r) {
      std::copy_n(A_.begin() + static_cast<std::ptrdiff_t>(r * C_), C_, M_.begin() + static_cast<std::ptrdiff_t>(r * C2));
      for (std::size_t k = 0; k < nm; ++k) M_[r * C2 + C_ + k] = -A_[r * C_ + cnt + k];
      c_[r] = b_[r];
    }
    for (std::size_t k = 0; k < nm; ++k) M_[(R + k) * C2 + C_ + k] = kSignedPenalty;
    if (!signed_solver_) signed_solver_.emplace(static_cast<int>(R2), static_cast<int>(C2));  // grows on demand
    z_.assign(C2, 0.0);
    NnlsResult r = signed_solver_->solve(M_.data(), static_cast<int>(R2), static_cast<int>(C2), c_.data(), z_.data(), options,
                                         MatrixOrder::RowMajor);
    x_.assign(z_.begin(), z_.begin() + static_cast<std::ptrdiff_t>(C_));
    for (std::size_t k = 0; k < nm; ++k) x_[cnt + k] -= z_[C_ + k];
    r.residual = residual();
    return r;
  }

  // ||A x - b|| of the current system (A_, b_) at x_.
  Real residual() const {
    const Eigen::Map<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(A_.data(), rows_, static_cast<Eigen::Index>(C_));
    return (A * Eigen::Map<const Eigen::VectorXd>(x_.data(), static_cast<Eigen::Index>(C_)) -
            Eigen::Map<const Eigen::VectorXd>(b_.data(), rows_))
        .norm();
  }

  // The estimated error the row in x_ (degree `deg` over columns_) makes at its particle: on u
  // with |D^α u| <= k^|α| its truncation's leading part is (k h)^m Σ_|α|=m |T_α| / α! over h^2,
  // m = deg + 1 and T_α the row's residual on the scaled monomial e^α, and it moves u_i by
  // that over the diagonal Σ w (the h^2 cancels). Only the rows that fall back use it.
  Real truncation_estimate(Index i, int deg) {
    const int m = deg + 1;
    build_system(i, m);  // the same columns: x_ still matches them
    Real sum = 0;
    for (const auto& [r, factorial] : t_.top[static_cast<std::size_t>(m)]) {
      Real t = 0;
      for (std::size_t k = 0; k < C_; ++k) t += A_[r * C_ + k] * x_[k];
      sum += std::abs(t) / factorial;
    }
    // A row's defect τ moves its own value by about τ over its diagonal Σ_j w_j (the
    // neighbours held): a row with the larger diagonal gives the smaller error.
    Real diagonal = 0;
    for (std::size_t k = 0; k < columns_.size(); ++k) diagonal += x_[k] * scale_[columns_[k]];
    return diagonal > 0 ? std::pow(wave_number_ * h_, m) * sum / diagonal : std::numeric_limits<Real>::infinity();
  }

  // Row i takes the solution in x_ (degree `deg` over columns_): its weights into the target.
  void accept(Index i, int deg, bool signed_mu) {
    const auto si = static_cast<std::size_t>(i);
    const auto nbr = candidates_;
    const std::size_t cnt = columns_.size();
    const bool wall = wall_row(i);
    h_ = disc_.neighbours.radius(i);
    out_.ok[si] = 1;
    out_.degree[si] = static_cast<char>(deg);
    out_.residual[si] = residual_;
    bool negative = false;
    for (std::size_t k = cnt; k <= 2 * cnt; ++k) negative = negative || x_[k] < 0;
    out_.signed_average[si] = signed_mu && negative;
    out_.mu_self[si] = x_[2 * cnt];
    if (wall) out_.wall_flux[si] = x_[2 * cnt + 1] / h_;
    if (wide_) return accept_wide(i);
    if (cnt < nbr.size())  // the neighbours left out of an inner row weigh nothing
      for (std::size_t j = 0; j < nbr.size(); ++j) {
        const auto slot = static_cast<std::size_t>(neighbour_slot(target_, i, static_cast<Index>(j)));
        target_.values[0][slot] = 0;
        target_.rhs[slot] = 0;
      }
    for (std::size_t k = 0; k < cnt; ++k) {
      const std::size_t j = columns_[k];
      const auto slot = static_cast<std::size_t>(neighbour_slot(target_, i, static_cast<Index>(j)));
      target_.values[0][slot] = x_[k] * scale_[j] / (h_ * h_);
      target_.rhs[slot] = x_[cnt + k] * scale_[j];
    }
  }

 public:
  // Row i again over every particle within CompactRowOptions::wide_support times its radius
  // that a neighbour's list holds (with a covering radius below (2 - wide_support) / 2 of
  // the support, every particle of that ball: the lens the two supports share holds one),
  // where its neighbours admit no positive row of the top degree. True, and the row in `row`
  // (the stencil's pattern cannot hold it), when the wider support admits one; else row i is
  // left as solve() made it.
  bool solve_wide(Index i, RowReplacement& row) {
    const NeighbourList& nl = disc_.neighbours;
    wide_row_ = -1;
    const PointCloud& cloud = disc_.cloud;
    const auto si = static_cast<std::size_t>(i);
    const Vec3& xi = cloud.positions[si];
    const Real reach = options_.wide_support * nl.radius(i);
    // Two images of one particle lie a period apart: on a box shorter than two reaches (a
    // period between 2 h, the least a support allows, and 2.5 h) the ball could hold both, and
    // the folded row one column twice. Such rows keep what their own support gave.
    if (cloud.domain.shortest_period() <= 2 * reach) return false;
    wide_candidates_.clear();
    for (const Index k : nl.of(i)) {
      wide_candidates_.push_back(k);
      for (const Index j : nl.of(k))
        if (j != i && (cloud.positions[static_cast<std::size_t>(j)] - xi).squaredNorm() <= reach * reach)
          wide_candidates_.push_back(j);
    }
    std::sort(wide_candidates_.begin(), wide_candidates_.end());
    wide_candidates_.erase(std::unique(wide_candidates_.begin(), wide_candidates_.end()), wide_candidates_.end());
    if (wide_candidates_.size() == static_cast<std::size_t>(nl.count(i))) return false;  // nobody beyond the support
    wide_distances_.resize(wide_candidates_.size());
    for (std::size_t k = 0; k < wide_candidates_.size(); ++k)
      wide_distances_[k] = (cloud.positions[static_cast<std::size_t>(wide_candidates_[k])] - xi).norm();
    wide_row_ = i;
    candidates_ = wide_candidates_;
    column_scales(wide_distances_, scale_);
    all_columns(wide_candidates_.size());
    const Real residual_before = out_.residual[si];
    wide_ = &row;
    // Held to the test of a signed row: where a jumps by orders of magnitude (a channelised
    // medium) a positive row over the wider support can weigh the average of f alone and
    // leave the particle without a diagonal (no w), unconnected.
    const bool found = solve_degree(i, options_.degree, false) && laplacian_type(i, columns_.size());
    if (found) accept(i, options_.degree, false);
    else out_.residual[si] = residual_before;
    wide_ = nullptr;
    return found;
  }

 private:
  // The wide row in x_ as a replacement row: its columns sorted, the diagonal's value left for
  // the caller's difference form and its right-hand-side weight μ_ii.
  void accept_wide(Index i) {
    const std::size_t cnt = columns_.size();
    RowReplacement& row = *wide_;
    row.row = i;
    row.col.clear();
    row.values.assign(1, {});
    row.rhs.clear();
    bool self = false;
    for (std::size_t k = 0; k <= cnt; ++k) {
      if (!self && (k == cnt || candidates_[columns_[k]] > i)) {  // the diagonal in its place
        self = true;
        row.col.push_back(i);
        row.values[0].push_back(0);
        row.rhs.push_back(out_.mu_self[static_cast<std::size_t>(i)]);
      }
      if (k == cnt) break;
      const std::size_t j = columns_[k];
      if (x_[k] == 0 && x_[cnt + k] == 0) continue;  // a wide row keeps only the particles it weighs
      row.col.push_back(candidates_[j]);
      row.values[0].push_back(x_[k] * scale_[j] / (h_ * h_));
      row.rhs.push_back(x_[cnt + k] * scale_[j]);
    }
  }

  // The weight of ||μ-|| against the fit of the scaled system (entries O(1)): small enough
  // that the fit comes first (polish removes the residual it leaves), large enough that NNLS
  // keeps μ+ and μ- of one particle apart.
  static constexpr Real kSignedPenalty = 1e-2;

  const Discretisation& disc_;
  const Field* a_;
  const Eigen::MatrixXd* grad_a_;
  const MonomialTables& t_;
  const CompactRowOptions& options_;
  const Real wave_number_;
  const CompactWalls& walls_;
  Stencil& target_;
  CompactRows& out_;
  NnlsSolver solver_;
  DenseSimplex lp_;  ///< CompactRowOptions::least_truncation
  Real infeasible_bound_ = 0;  ///< the last program's LpResult::residual_bound where it was infeasible, else 0
  bool lp_stopped_ = false;    ///< the last program stopped at its pivot limit
  std::vector<Real> start_;    ///< least_truncation_from_nnls's start
  std::optional<NnlsSolver> signed_solver_;  ///< for the augmented systems of signed averages
  std::vector<Real> A_, b_, x_, scale_, vals_, M_, c_, z_, signed_x_, cost_;
  std::vector<std::size_t> columns_;  ///< the candidates (positions in candidates_) of the current attempt
  std::span<const Index> candidates_;  ///< the particles row i may weigh: its neighbours, or wide_candidates_
  std::vector<Index> wide_candidates_;
  std::vector<Real> wide_distances_;
  RowReplacement* wide_ = nullptr;  ///< where accept() puts a wide row (null: into the stencil's pattern)
  Index wide_row_ = -1;             ///< the row whose wider support wide_candidates_ holds
  std::array<std::array<Real, 8>, 3> pw_{};
  std::size_t C_ = 0;  ///< columns of the current system
  int rows_ = 0;       ///< its rows
  Real h_ = 0;         ///< the current particle's support radius
  Real residual_ = 0;  ///< the residual of the solution in x_
};
}  // namespace

CompactRows compact_rows(const Discretisation& disc, std::span<const char> rows, const Field* a, const Eigen::MatrixXd* grad_a,
                         const CompactRowOptions& options, Stencil& target, const CompactWalls& walls) {
  const PointCloud& cloud = disc.cloud;
  const NeighbourList& nl = disc.neighbours;
  const Index n = cloud.size();
  const int dim = cloud.dim;
  check<ConfigError>(options.min_degree >= 3 && options.min_degree <= options.degree && options.degree <= 6,
                     "compact rows: polynomial degrees ", options.min_degree, "..", options.degree, " outside 3..6");
  check<ConfigError>(options.inner_support > 0 && options.inner_support <= 1, "compact rows: the inner support must be a "
                     "fraction in (0, 1] of the support radius, got ", options.inner_support);
  check<ConfigError>(std::isfinite(options.wide_support) && options.wide_support >= 1 && options.wide_support < 2,
                     "compact rows: the wider support must be a multiple in [1, 2) of the support radius (1: none), got ",
                     options.wide_support);
  check<ConfigError>(std::isfinite(options.wave_number) && options.wave_number >= 0, "compact rows: the wave number of "
                     "the truncation estimate must be finite and >= 0 (0: from the cloud's extent), got ", options.wave_number);
  check<InputError>(!a || a->size() == n, "compact rows: coefficient has ", a ? a->size() : 0, " values for ", n, " particles");
  check<InputError>(!grad_a || (grad_a->rows() == n && grad_a->cols() == dim), "compact rows: grad a must be ", n, " x ", dim);
  check<InputError>(nl.distances.size() == nl.indices.size(), "compact rows need neighbour lists with cached distances");
  check<InputError>(target.rows() == n && !target.values.empty() && target.values[0].size() == static_cast<std::size_t>(target.nnz()) &&
                        target.rhs.size() == target.values[0].size() && target.nnz() == nl.total() + n,
                    "compact rows: the target must be the zero pattern of the neighbour list with a right-hand-side array");
  const bool any_wall = !walls.rows.empty();
  check<InputError>(!any_wall || (static_cast<Index>(walls.rows.size()) == n && static_cast<Index>(walls.conormal.size()) == n),
                    "compact rows: wall mask and conormals need one entry per particle");
  // Signed averages compare rows by their residuals one degree up
  // (and the least-truncation rows bound their residuals there).
  const MonomialTables tables(dim, options.min_degree,
                              options.degree + (options.signed_average || options.least_truncation ? 1 : 0));
  // The whole cloud's extent (on one rank's part too: the rows do not depend on the ranks).
  const Real wave_number = options.wave_number > 0 ? options.wave_number : std::numbers::pi / disc.length_unit();
  CompactRows out;
  out.ok.assign(static_cast<std::size_t>(n), 0);
  out.degree.assign(static_cast<std::size_t>(n), 0);
  out.mu_self.assign(static_cast<std::size_t>(n), 0.0);
  out.residual.assign(static_cast<std::size_t>(n), 0.0);
  out.signed_average.assign(static_cast<std::size_t>(n), 0);
  if (any_wall) out.wall_flux.assign(static_cast<std::size_t>(n), 0.0);
  Index max_count = 0;
  for (Index i = 0; i < n; ++i) max_count = std::max(max_count, nl.count(i));
  const auto wanted = [&](Index i) {
    const auto si = static_cast<std::size_t>(i);
    return rows.empty() ? cloud.tags[si] != Tag::Ghost : rows[si] != 0;
  };
  // The rows left without a positive row of the top degree over their own support, tried
  // again on the wider support.
  const bool try_wide = options.wide_support > 1;
  std::vector<char> deferred(try_wide ? static_cast<std::size_t>(n) : 0, 0);
  std::vector<Index> retry;
  std::vector<RowReplacement> wide;
  std::vector<char> widened;
#pragma omp parallel
  {
    CompactRowSolver thread_rows(disc, a, grad_a, tables, options, wave_number, walls, max_count, target, out);
#pragma omp for schedule(dynamic, 64)
    for (Index i = 0; i < n; ++i) {
      if (!wanted(i) || interrupt_pending(i)) continue;  // (after a stop request: skipped, see below)
      const bool defer = thread_rows.solve(i, try_wide);
      if (defer) deferred[static_cast<std::size_t>(i)] = 1;
    }
    if (try_wide) {
#pragma omp single
      {
        for (Index i = 0; i < n; ++i)
          if (deferred[static_cast<std::size_t>(i)]) retry.push_back(i);
        wide.resize(retry.size());
        widened.assign(retry.size(), 0);
      }
      // The wider support first: where it admits a positive row of the top degree that row is
      // kept, so the lower degrees over the row's own support (the signed averages, with
      // their larger systems) are worked out only where it does not.
#pragma omp for schedule(dynamic, 1)
      for (std::size_t r = 0; r < retry.size(); ++r) {
        if (interrupt_pending(retry[r])) continue;
        widened[r] = thread_rows.solve_wide(retry[r], wide[r]);
        if (!widened[r] && options.wide_lower_degrees) widened[r] = thread_rows.wide_lower_degrees(retry[r], wide[r]);
        if (!widened[r]) thread_rows.lower_degrees(retry[r]);
      }
    }
  }
  check_interrupt();  // rows skipped after a stop request: the result is incomplete
  out.wide_attempted = static_cast<Index>(retry.size());
  for (std::size_t r = 0; r < retry.size(); ++r)
    if (widened[r]) out.wide.push_back(std::move(wide[r]));
  return out;
}

}  // namespace vrsph
