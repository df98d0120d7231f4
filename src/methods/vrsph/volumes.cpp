// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <optional>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/methods/vrsph/signed_volumes.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>

namespace vrsph {

namespace {
// Nearer neighbours first: the n columns of the rows x n moment matrix scaled by
// nearest_first_scales (kept in `scale`: the volumes found are multiplied by them).
void prefer_near(std::span<const Real> dist, Real* A, std::size_t rows, MatrixOrder order, std::vector<Real>& scale) {
  nearest_first_scales(dist, scale);
  const std::size_t n = dist.size();
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t r = 0; r < rows; ++r) (order == MatrixOrder::RowMajor ? A[r * n + j] : A[j * rows + r]) *= scale[j];
}
}  // namespace

namespace {
// Y = -2 W'/r has the units of length^-(d+2): in units of `length` it is Y length^(d+2), and
// half_y = -W'/r times this (a pow per row was 1% of a rebuild: none for the unit length).
Real half_y_scale(Real length, int dim) { return length == 1 ? -1.0 : -std::pow(length, dim + 2); }
}  // namespace

void neighbour_geometry(const Discretisation& disc, Index i, const Kernel& ker, Vec3* xji, Real* half_y, Real length) {
  const auto nbr = disc.neighbours.of(i);
  const auto dist = disc.neighbours.distances_of(i);
  const int cnt = static_cast<int>(nbr.size());
  ker.dW_over_r(dist.data(), half_y, cnt);
  const Vec3& xi = disc.cloud.positions[static_cast<std::size_t>(i)];
  const Real y_scale = half_y_scale(length, disc.cloud.dim);
  for (int k = 0; k < cnt; ++k) {
    xji[k] = (disc.neighbour_position(i, k) - xi) / length;
    half_y[k] *= y_scale;
  }
}


ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows, const NnlsOptions& nnls, MomentRows layout,
                                         std::span<const MomentTarget> targets) {
  VolumeOptions o;
  o.nnls = nnls;
  o.layout = layout;
  return reconstruct_volumes(disc, conditions, rows, o, targets);
}

namespace {
// One thread's rows of a reconstruction: per-thread workspaces sized once, so that the
// particle loop allocates nothing (the signed and balance rows, a thin layer, allocate in
// their own solvers). Every moment system is in units of the cloud's extent (length_scale):
// the same systems, NNLS tolerances and least-squares fits of infeasible rows in metres or
// millimetres (1 for the papers' unit boxes, whose numbers are unchanged); volumes come out
// in length^d and are scaled back; first-moment targets (grad m) and the wall flux carry one
// length more or less.
class VolumeRows {
 public:
  VolumeRows(const Discretisation& disc, MomentConditions conditions, const VolumeOptions& opt,
             std::span<const MomentTarget> targets, int m, int mw, Index max_count, ReconstructedVolumes& out)
      : disc_(disc), nl_(disc.neighbours), conditions_(conditions), opt_(opt), targets_(targets), m_(m), mw_(mw),
        max_count_(max_count), length_(disc.length_unit()), volume_unit_(std::pow(length_, disc.cloud.dim)), out_(out), solver_(m, static_cast<int>(max_count)),
        A_(static_cast<std::size_t>(std::max(m, mw)) * (static_cast<std::size_t>(max_count) + 1)),
        b_(static_cast<std::size_t>(std::max(m, mw))), half_y_(static_cast<std::size_t>(max_count)),
        xji_(static_cast<std::size_t>(max_count)) {}

  // Row i's volumes into v (and its wall flux, residual and counts into the output).
  void solve(Index i, Real* v) {
    const auto si = static_cast<std::size_t>(i);
    // The kernel changes only with the support radius (the same for every particle unless
    // h varies): rebuilding it per particle (a pow and checks) was ~2% of the volumes.
    if (!ker_ || nl_.radius(i) != ker_->support()) ker_ = disc_.kernel_at(i);
    const bool wall = !opt_.wall.rows.empty() && opt_.wall.rows[si];
    const bool warm = !wall && guess(i);
    if (warm) ++warm_rows_;
    const bool square = warm && square_row(i, v);
    if (square) {
      ++warm_hits_;
    } else {
      neighbour_geometry(disc_, i, *ker_, xji_.data(), half_y_.data(), length_);
      if (wall) wall_row(i, v);
      else interior_row(i, v, warm);
      signed_fallback(i, v, wall);
    }
    if (opt_.record_active) {
      if (square) record_guess(i);
      else record_active(i, v);
    }
    if (length_ == 1) return;
    for (Index j = 0; j < nl_.count(i); ++j) v[j] *= volume_unit_;
    if (wall) out_.wall_flux[si] /= length_;
  }
  // This thread's warm-started rows and those the guess solved as it stood.
  Index warm_rows() const { return warm_rows_; }
  Index warm_hits() const { return warm_hits_; }

 private:
  void targets_in_units(MomentConditions c, Real* rhs) const {
    if (length_ == 1) return;
    for (int k = 0; k < disc_.cloud.dim; ++k) rhs[first_moment_row(c, disc_.cloud.dim, opt_.layout, k)] *= length_;
  }

  void record(Index i, const NnlsResult& r) {
    const auto si = static_cast<std::size_t>(i);
    out_.residual[si] = r.residual;
    out_.failed[si] = r.status != NnlsStatus::Converged;
    out_.iterations[si] = r.iterations;
    out_.positive[si] = r.passive;
  }

  // The warm start's fast path: a guess of m columns (the previous vertex) whose square moment
  // system still has a positive solution is this row's optimum (residual zero), found from the
  // m guessed neighbours alone: no kernel values, moment columns or NNLS for the others. False
  // (nothing written) when the guess has another size, is singular or is no longer positive.
  bool square_row(Index i, Real* v) {
    if (static_cast<int>(guess_.size()) != m_) return false;
    const int dim = disc_.cloud.dim, cnt = static_cast<int>(nl_.count(i));
    const auto M = static_cast<std::size_t>(m_);
    const auto dist = nl_.distances_of(i);
    const Vec3& xi = disc_.cloud.positions[static_cast<std::size_t>(i)];
    const Real y_scale = half_y_scale(length_, dim);
    guess_r_.resize(M);
    for (std::size_t c = 0; c < M; ++c) {
      const auto k = static_cast<std::size_t>(guess_[c]);
      xji_[c] = (disc_.neighbour_position(i, static_cast<Index>(k)) - xi) / length_;
      guess_r_[c] = dist[k];
    }
    // The kernel's batched form, as neighbour_geometry computes a fresh row's: the moment
    // columns are now those of a fresh build bit for bit (the scalar form differs in the last
    // bits), and no branch per neighbour on which piece of the spline its distance falls in
    // (those lines took about 6 % of an update step's samples, perf; the batched call 2.5 %).
    ker_->dW_over_r(guess_r_.data(), half_y_.data(), m_);
    for (std::size_t c = 0; c < M; ++c) half_y_[c] *= y_scale;
    build_moment_system(conditions_, dim, xji_.data(), half_y_.data(), m_, A_.data(), b_.data(), opt_.layout,
                        MatrixOrder::ColumnMajor);
    if (!targets_.empty()) {
      moment_targets(conditions_, dim, opt_.layout, targets_[static_cast<std::size_t>(i)], b_.data());
      targets_in_units(conditions_, b_.data());
    }
    Real a_norm1 = 0;
    for (std::size_t c = 0; c < M; ++c) {
      Real sum = 0;
      for (std::size_t r = 0; r < M; ++r) sum += std::abs(A_[c * M + r]);
      a_norm1 = std::max(a_norm1, sum);
    }
    lu_.assign(A_.begin(), A_.begin() + static_cast<std::ptrdiff_t>(M * M));
    z_.assign(b_.begin(), b_.begin() + static_cast<std::ptrdiff_t>(M));
    if (!solve_square_positive(lu_.data(), m_, z_.data(), nnls_value_tolerance(a_norm1, m_, cnt))) return false;
    std::fill(v, v + cnt, 0.0);
    Real r2 = 0;
    for (std::size_t r = 0; r < M; ++r) {
      Real ar = -b_[r];
      for (std::size_t c = 0; c < M; ++c) ar += A_[c * M + r] * z_[c];
      r2 += ar * ar;
    }
    for (std::size_t c = 0; c < M; ++c) v[guess_[c]] = z_[c];
    NnlsResult res;
    res.passive = m_;
    res.residual = std::sqrt(r2);
    res.warm_kept = m_;
    record(i, res);
    return true;
  }

  void interior_row(Index i, Real* v, bool warm) {
    const int dim = disc_.cloud.dim, cnt = static_cast<int>(nl_.count(i));
    rows_ = m_;
    // Row-major: the layout the solver works on, so it copies nothing.
    build_moment_system(conditions_, dim, xji_.data(), half_y_.data(), cnt, A_.data(), b_.data(), opt_.layout,
                        MatrixOrder::RowMajor);
    if (!targets_.empty()) {
      moment_targets(conditions_, dim, opt_.layout, targets_[static_cast<std::size_t>(i)], b_.data());
      targets_in_units(conditions_, b_.data());
    }
    if (opt_.prefer_near) prefer_near(nl_.distances_of(i), A_.data(), static_cast<std::size_t>(m_), MatrixOrder::RowMajor, near_);
    const NnlsResult r = solver_.solve(A_.data(), m_, cnt, b_.data(), v, opt_.nnls, MatrixOrder::RowMajor,
                                       warm ? std::span<const int>(guess_) : std::span<const int>());
    if (warm && r.iterations == 0 && r.warm_kept == static_cast<int>(guess_.size())) ++warm_hits_;  // held, off the fast path
    if (opt_.prefer_near)
      for (int j = 0; j < cnt; ++j) v[j] *= near_[static_cast<std::size_t>(j)];
    record(i, r);
  }

  void record_active(Index i, const Real* v) {
    ActiveSets& a = out_.active;
    const auto si = static_cast<std::size_t>(i), stride = static_cast<std::size_t>(a.stride);
    const auto row = nl_.of(i);
    std::size_t c = 0;
    for (std::size_t k = 0; k < row.size() && c < stride; ++k)
      if (v[k] > 0) a.particles[si * stride + c++] = row[k];
    a.count[si] = static_cast<std::uint8_t>(c);
  }

  // The same for a row the guess solved (square_row): its volumes are positive at exactly the
  // guessed columns (ascending), so the row's other entries need not be scanned.
  void record_guess(Index i) {
    ActiveSets& a = out_.active;
    const auto si = static_cast<std::size_t>(i), stride = static_cast<std::size_t>(a.stride);
    const auto row = nl_.of(i);
    const std::size_t c = std::min(guess_.size(), stride);
    for (std::size_t p = 0; p < c; ++p) a.particles[si * stride + p] = row[static_cast<std::size_t>(guess_[p])];
    a.count[si] = static_cast<std::uint8_t>(c);
  }

  // Row i's warm-start guess as column numbers of its current neighbour row (both sorted by
  // particle index: one merge). False (guess_ empty) when there is none.
  bool guess(Index i) {
    guess_.clear();
    const ActiveSets* w = opt_.warm_start;
    if (!w || w->empty()) return false;
    const auto si = static_cast<std::size_t>(i), stride = static_cast<std::size_t>(w->stride);
    const auto row = nl_.of(i);
    std::size_t k = 0;
    for (std::size_t p = 0; p < w->count[si]; ++p) {
      const Index j = w->particles[si * stride + p];
      while (k < row.size() && row[k] < j) ++k;
      if (k == row.size()) break;
      if (row[k] == j) guess_.push_back(static_cast<int>(k));
    }
    return true;
  }

  // Columns: the neighbours, then the wall flux along the conormal in the first-moment rows,
  // scaled like the largest neighbour column so that NNLS's tests treat it alike.
  void wall_row(Index i, Real* v) {
    const auto si = static_cast<std::size_t>(i);
    const int dim = disc_.cloud.dim, cnt = static_cast<int>(nl_.count(i));
    const auto ucnt = static_cast<std::size_t>(cnt), ur = static_cast<std::size_t>(mw_);
    rows_ = mw_;
    build_moment_system(MomentConditions::WallLaplace, dim, xji_.data(), half_y_.data(), cnt, A_.data(), b_.data(),
                        opt_.layout, MatrixOrder::ColumnMajor);
    if (!targets_.empty()) {
      moment_targets(MomentConditions::WallLaplace, dim, opt_.layout, targets_[si], b_.data());
      targets_in_units(MomentConditions::WallLaplace, b_.data());
    }
    // Nearer neighbours first (prefer_near): on a lattice NNLS otherwise takes the diagonal
    // neighbours only, and the wall rows, like VRSPH's interior rows there, leave the two
    // checkerboard sublattices uncoupled: a pure Neumann problem then has two constants.
    prefer_near(nl_.distances_of(i), A_.data(), ur, MatrixOrder::ColumnMajor, near_);
    kappa_ = 0;
    for (std::size_t j = 0; j < ucnt; ++j) {
      Real s2 = 0;
      for (std::size_t r = 0; r < ur; ++r) s2 += A_[j * ur + r] * A_[j * ur + r];
      kappa_ = std::max(kappa_, std::sqrt(s2));
    }
    if (kappa_ == 0) kappa_ = 1;
    Real* flux_col = A_.data() + ucnt * ur;
    std::fill(flux_col, flux_col + ur, 0.0);
    for (int k = 0; k < dim; ++k)
      flux_col[first_moment_row(MomentConditions::WallLaplace, dim, opt_.layout, k)] = kappa_ * opt_.wall.conormal[si][k];
    xw_.assign(ucnt + 1, 0.0);
    if (!wall_solver_) wall_solver_.emplace(mw_, static_cast<int>(max_count_) + 1);
    const NnlsResult r = wall_solver_->solve(A_.data(), mw_, cnt + 1, b_.data(), xw_.data(), opt_.nnls, MatrixOrder::ColumnMajor);
    for (std::size_t j = 0; j < ucnt; ++j) v[j] = xw_[j] * near_[j];
    out_.wall_flux[si] = 2 * kappa_ * xw_[ucnt];
    record(i, r);
  }

  // Signed fallback on the same columns (row-major copy; for a balance row the wall flux is
  // one more column and may turn negative as well), never worse than the NNLS fit.
  void signed_fallback(Index i, Real* v, bool wall) {
    const auto si = static_cast<std::size_t>(i);
    const auto ucnt = static_cast<std::size_t>(nl_.count(i)), ur = static_cast<std::size_t>(rows_);
    Real bnorm = 0;
    for (std::size_t r = 0; r < ur; ++r) bnorm += b_[r] * b_[r];
    bnorm = std::sqrt(bnorm);
    if (opt_.infeasible != InfeasibleRowPolicy::Signed || !(out_.residual[si] > opt_.signed_threshold * bnorm)) return;
    const std::size_t cols = wall ? ucnt + 1 : ucnt;
    Aw_.resize(ur * cols);
    if (wall)
      for (std::size_t r = 0; r < ur; ++r)
        for (std::size_t j = 0; j < cols; ++j) Aw_[r * cols + j] = A_[j * ur + r];
    else
      std::copy(A_.begin(), A_.begin() + static_cast<std::ptrdiff_t>(ur * cols), Aw_.begin());
    xw_.assign(cols, 0.0);
    if (!signed_solver_) signed_solver_.emplace();
    const SignedVolumesResult sr = signed_solver_->solve(Aw_.data(), rows_, static_cast<int>(cols), b_.data(), xw_.data());
    if (!(sr.residual < out_.residual[si])) return;
    for (std::size_t j = 0; j < ucnt; ++j) v[j] = wall || opt_.prefer_near ? xw_[j] * near_[j] : xw_[j];
    if (wall) out_.wall_flux[si] = 2 * kappa_ * xw_[ucnt];
    out_.residual[si] = sr.residual;
    out_.failed[si] = 0;
    out_.signed_row[si] = 1;
    out_.negative[si] = sr.negative;
  }

  const Discretisation& disc_;
  const NeighbourList& nl_;
  const MomentConditions conditions_;
  const VolumeOptions& opt_;
  std::span<const MomentTarget> targets_;
  const int m_, mw_;
  const Index max_count_;
  const Real length_, volume_unit_;
  ReconstructedVolumes& out_;
  NnlsSolver solver_;
  std::vector<Real> A_, b_, half_y_, Aw_, xw_, near_;
  std::vector<Vec3> xji_;
  std::vector<int> guess_;    ///< the current row's warm-start columns
  std::vector<Real> guess_r_;  ///< their distances
  std::vector<Real> lu_, z_;  ///< square_row's LU factors and solution
  Index warm_rows_ = 0, warm_hits_ = 0;
  std::optional<Kernel> ker_;
  std::optional<SignedVolumeSolver> signed_solver_;
  std::optional<NnlsSolver> wall_solver_;
  int rows_ = 0;     ///< moment rows of the current row's system
  Real kappa_ = 0;   ///< the wall column's scale of the current balance row
};

// The output arrays sized for this reconstruction, their storage reused.
void reset_volumes(MomentConditions conditions, Index n, Index pairs, bool walls, ReconstructedVolumes& out) {
  out.conditions = conditions;
  resize_for_overwrite(out.v, static_cast<std::size_t>(pairs));  // every row writes its slots
  out.residual.assign(static_cast<std::size_t>(n), 0.0);
  out.failed.assign(static_cast<std::size_t>(n), 0);
  out.iterations.assign(static_cast<std::size_t>(n), 0);
  out.positive.assign(static_cast<std::size_t>(n), 0);
  out.signed_row.assign(static_cast<std::size_t>(n), 0);
  out.negative.assign(static_cast<std::size_t>(n), 0);
  out.wall_flux.clear();
  if (walls) out.wall_flux.assign(static_cast<std::size_t>(n), 0.0);
  out.warm_rows = out.warm_hits = 0;
}
}  // namespace

ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows, const VolumeOptions& opt,
                                         std::span<const MomentTarget> targets) {
  ReconstructedVolumes out;
  reconstruct_volumes(disc, conditions, rows, opt, targets, out);
  return out;
}

void reconstruct_volumes(const Discretisation& disc, MomentConditions conditions, std::span<const char> rows,
                         const VolumeOptions& opt, std::span<const MomentTarget> targets, ReconstructedVolumes& out) {
  const PointCloud& cloud = disc.cloud;
  const NeighbourList& nl = disc.neighbours;
  const Index n = cloud.size();
  check<InputError>(rows.empty() || static_cast<Index>(rows.size()) == n, "volume reconstruction: row mask has ",
                    rows.size(), " entries for ", n, " particles");
  check<InputError>(nl.distances.size() == nl.indices.size(), "VRSPH needs neighbour lists with cached distances");
  check<InputError>(!opt.warm_start || opt.warm_start->empty() || opt.warm_start->count.size() == static_cast<std::size_t>(n),
                    "volume reconstruction: warm-start sets for ", opt.warm_start ? opt.warm_start->count.size() : 0,
                    " particles, the cloud has ", n, " (a rebuild on another cloud?)");
  check<InputError>(targets.empty() || (conditions == MomentConditions::Laplace && static_cast<Index>(targets.size()) == n),
                    "volume reconstruction: ", targets.size(), " moment targets for ", n, " particles (Laplace only)");
  const bool walls = !opt.wall.rows.empty();
  check<InputError>(!walls || (conditions == MomentConditions::Laplace && static_cast<Index>(opt.wall.rows.size()) == n &&
                               static_cast<Index>(opt.wall.conormal.size()) == n),
                    "volume reconstruction: balance rows need the Laplace conditions and a row mask and conormal per "
                    "particle (", opt.wall.rows.size(), " and ", opt.wall.conormal.size(), " for ", n, ")");
  const int m = moment_rows(conditions, cloud.dim, opt.layout);
  const int mw = walls ? moment_rows(MomentConditions::WallLaplace, cloud.dim, opt.layout) : 0;
  reset_volumes(conditions, n, nl.total(), walls, out);
  if (opt.record_active) {
    out.active.stride = std::max(m, mw);
    out.active.particles.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(out.active.stride));
    out.active.count.assign(static_cast<std::size_t>(n), 0);
  }
  Index max_count = 0;
  for (Index i = 0; i < n; ++i) max_count = std::max(max_count, nl.count(i));
#pragma omp parallel
  {
    VolumeRows thread_rows(disc, conditions, opt, targets, m, mw, max_count, out);
#pragma omp for schedule(dynamic, 64)
    for (Index i = 0; i < n; ++i) {
      const auto si = static_cast<std::size_t>(i);
      Real* v = out.v.data() + nl.offsets[si];
      const bool wanted = rows.empty() ? cloud.tags[si] != Tag::Ghost : rows[si] != 0;
      if (!wanted || interrupt_pending(i)) {  // (a stop asked for: the rest is skipped, see below)
        std::fill(v, v + nl.count(i), 0.0);
        continue;
      }
      thread_rows.solve(i, v);
    }
#pragma omp critical(vrsph_warm_counts)
    {
      out.warm_rows += thread_rows.warm_rows();
      out.warm_hits += thread_rows.warm_hits();
    }
  }
  check_interrupt();  // rows skipped after a stop request: the volumes are incomplete
}

}  // namespace vrsph
