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

void neighbour_geometry(const Discretisation& disc, Index i, const Kernel& ker, Vec3* xji, Real* half_y, Real length) {
  const auto nbr = disc.neighbours.of(i);
  const auto dist = disc.neighbours.distances_of(i);
  const int cnt = static_cast<int>(nbr.size());
  ker.dW_over_r(dist.data(), half_y, cnt);
  const Vec3& xi = disc.cloud.positions[static_cast<std::size_t>(i)];
  // Y = -2 W'/r has the units of length^-(d+2): in units of `length` it is Y length^(d+2).
  const Real y_scale = -std::pow(length, disc.cloud.dim + 2);
  for (int k = 0; k < cnt; ++k) {
    xji[k] = (disc.cloud.positions[static_cast<std::size_t>(nbr[static_cast<std::size_t>(k)])] - xi) / length;
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

ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows, const VolumeOptions& opt,
                                         std::span<const MomentTarget> targets) {
  const PointCloud& cloud = disc.cloud;
  const NeighbourList& nl = disc.neighbours;
  const Index n = cloud.size();
  const MomentRows layout = opt.layout;
  check<InputError>(rows.empty() || static_cast<Index>(rows.size()) == n, "volume reconstruction: row mask has ",
                    rows.size(), " entries for ", n, " particles");
  check<InputError>(nl.distances.size() == nl.indices.size(), "VRSPH needs neighbour lists with cached distances");
  check<InputError>(targets.empty() || (conditions == MomentConditions::Laplace && static_cast<Index>(targets.size()) == n),
                    "volume reconstruction: ", targets.size(), " moment targets for ", n, " particles (Laplace only)");
  const bool walls = !opt.wall.rows.empty();
  check<InputError>(!walls || (conditions == MomentConditions::Laplace && static_cast<Index>(opt.wall.rows.size()) == n &&
                               static_cast<Index>(opt.wall.conormal.size()) == n),
                    "volume reconstruction: balance rows need the Laplace conditions and a row mask and conormal per "
                    "particle (", opt.wall.rows.size(), " and ", opt.wall.conormal.size(), " for ", n, ")");
  const int dim = cloud.dim;
  const int m = moment_rows(conditions, dim, layout);
  const int mw = walls ? moment_rows(MomentConditions::WallLaplace, dim, layout) : 0;
  ReconstructedVolumes out;
  out.conditions = conditions;
  out.v.resize(static_cast<std::size_t>(nl.total()));
  out.residual.assign(static_cast<std::size_t>(n), 0.0);
  out.failed.assign(static_cast<std::size_t>(n), 0);
  out.iterations.assign(static_cast<std::size_t>(n), 0);
  out.positive.assign(static_cast<std::size_t>(n), 0);
  out.signed_row.assign(static_cast<std::size_t>(n), 0);
  out.negative.assign(static_cast<std::size_t>(n), 0);
  if (walls) out.wall_flux.assign(static_cast<std::size_t>(n), 0.0);
  Index max_count = 0;
  for (Index i = 0; i < n; ++i) max_count = std::max(max_count, nl.count(i));
  // Every moment system in units of the cloud's extent (length_scale): the same systems,
  // NNLS tolerances and least-squares fits of infeasible rows in metres or millimetres (1 for
  // the papers' unit boxes, whose numbers are unchanged): volumes
  // come out in length^d and are scaled back; first-moment targets (grad m) and the wall
  // flux carry one length more or less.
  const Real length = disc.length_unit(), volume_unit = std::pow(length, dim);
  const auto targets_in_units = [&](MomentConditions c, Real* rhs) {
    if (length == 1) return;
    for (int k = 0; k < dim; ++k) rhs[first_moment_row(c, dim, layout, k)] *= length;
  };
  const auto mc = static_cast<std::size_t>(max_count);
#pragma omp parallel
  {
    // Per-thread workspaces, sized once: no allocation inside the particle loop (the signed
    // and balance rows, a thin layer, allocate in their own solvers).
    NnlsSolver solver(m, static_cast<int>(max_count));
    std::vector<Real> A(static_cast<std::size_t>(std::max(m, mw)) * (mc + 1)), b(static_cast<std::size_t>(std::max(m, mw))),
        half_y(mc), Aw, xw, near_;
    std::vector<Vec3> xji(mc);
    std::optional<Kernel> ker;
    std::optional<SignedVolumeSolver> signed_solver;
    std::optional<NnlsSolver> wall_solver;
#pragma omp for schedule(dynamic, 64)
    for (Index i = 0; i < n; ++i) {
      const auto si = static_cast<std::size_t>(i);
      Real* v = out.v.data() + nl.offsets[si];
      const int cnt = static_cast<int>(nl.count(i));
      const auto ucnt = static_cast<std::size_t>(cnt);
      const bool wanted = rows.empty() ? cloud.tags[si] != Tag::Ghost : rows[si] != 0;
      if (!wanted || interrupt_pending(i)) {  // (a stop asked for: the rest is skipped, see below)
        std::fill(v, v + cnt, 0.0);
        continue;
      }
      // One row's volumes in units of `length` (returns early where the NNLS fit stands).
      const auto solve_row = [&] {
        // The kernel changes only with the support radius (the same for every particle unless
        // h varies): rebuilding it per particle (a pow and checks) was ~2% of the volumes.
        if (!ker || nl.radius(i) != ker->support()) ker = disc.kernel_at(i);
        neighbour_geometry(disc, i, *ker, xji.data(), half_y.data(), length);
        const bool wall = walls && opt.wall.rows[si];
        const int rows_i = wall ? mw : m;
        const auto ur = static_cast<std::size_t>(rows_i);
        Real bnorm = 0, kappa = 0;
        if (!wall) {
          // Row-major: the layout the solver works on, so it copies nothing.
          build_moment_system(conditions, dim, xji.data(), half_y.data(), cnt, A.data(), b.data(), layout, MatrixOrder::RowMajor);
          if (!targets.empty()) {
            moment_targets(conditions, dim, layout, targets[si], b.data());
            targets_in_units(conditions, b.data());
          }
          if (opt.prefer_near) prefer_near(nl.distances_of(i), A.data(), static_cast<std::size_t>(m), MatrixOrder::RowMajor, near_);
          const NnlsResult r = solver.solve(A.data(), m, cnt, b.data(), v, opt.nnls, MatrixOrder::RowMajor);
          if (opt.prefer_near)
            for (std::size_t j = 0; j < ucnt; ++j) v[j] *= near_[j];
          out.residual[si] = r.residual;
          out.failed[si] = r.status != NnlsStatus::Converged;
          out.iterations[si] = r.iterations;
          out.positive[si] = r.passive;
        } else {
          // Columns: the neighbours, then the wall flux along the conormal in the first-moment
          // rows, scaled like the largest neighbour column so that NNLS's tests treat it alike.
          build_moment_system(MomentConditions::WallLaplace, dim, xji.data(), half_y.data(), cnt, A.data(), b.data(), layout,
                              MatrixOrder::ColumnMajor);
          if (!targets.empty()) {
            moment_targets(MomentConditions::WallLaplace, dim, layout, targets[si], b.data());
            targets_in_units(MomentConditions::WallLaplace, b.data());
          }
          // Nearer neighbours first (prefer_near): on a lattice NNLS otherwise takes the diagonal
          // neighbours only, and the wall rows, like VRSPH's interior rows there, leave the two
          // checkerboard sublattices uncoupled: a pure Neumann problem then has two constants.
          prefer_near(nl.distances_of(i), A.data(), ur, MatrixOrder::ColumnMajor, near_);
          for (std::size_t j = 0; j < ucnt; ++j) {
            Real s2 = 0;
            for (std::size_t r = 0; r < ur; ++r) s2 += A[j * ur + r] * A[j * ur + r];
            kappa = std::max(kappa, std::sqrt(s2));
          }
          if (kappa == 0) kappa = 1;
          Real* flux_col = A.data() + ucnt * ur;
          std::fill(flux_col, flux_col + ur, 0.0);
          for (int k = 0; k < dim; ++k)
            flux_col[first_moment_row(MomentConditions::WallLaplace, dim, layout, k)] = kappa * opt.wall.conormal[si][k];
          xw.assign(ucnt + 1, 0.0);
          if (!wall_solver) wall_solver.emplace(mw, static_cast<int>(max_count) + 1);
          const NnlsResult r = wall_solver->solve(A.data(), mw, cnt + 1, b.data(), xw.data(), opt.nnls, MatrixOrder::ColumnMajor);
          for (std::size_t j = 0; j < ucnt; ++j) v[j] = xw[j] * near_[j];
          out.wall_flux[si] = 2 * kappa * xw[ucnt];
          out.residual[si] = r.residual;
          out.failed[si] = r.status != NnlsStatus::Converged;
          out.iterations[si] = r.iterations;
          out.positive[si] = r.passive;
        }
        for (std::size_t r = 0; r < ur; ++r) bnorm += b[r] * b[r];
        bnorm = std::sqrt(bnorm);
        if (opt.infeasible != InfeasibleRowPolicy::Signed || !(out.residual[si] > opt.signed_threshold * bnorm)) return;
        // Signed fallback on the same columns (row-major copy; for a balance row the wall flux
        // is one more column and may turn negative as well).
        const std::size_t cols = wall ? ucnt + 1 : ucnt;
        Aw.resize(ur * cols);
        if (wall)
          for (std::size_t r = 0; r < ur; ++r)
            for (std::size_t j = 0; j < cols; ++j) Aw[r * cols + j] = A[j * ur + r];
        else
          std::copy(A.begin(), A.begin() + static_cast<std::ptrdiff_t>(ur * cols), Aw.begin());
        xw.assign(cols, 0.0);
        if (!signed_solver) signed_solver.emplace();
        const SignedVolumesResult sr = signed_solver->solve(Aw.data(), rows_i, static_cast<int>(cols), b.data(), xw.data());
        if (!(sr.residual < out.residual[si])) return;  // never worse than the NNLS fit
        for (std::size_t j = 0; j < ucnt; ++j) v[j] = wall || opt.prefer_near ? xw[j] * near_[j] : xw[j];
        if (wall) out.wall_flux[si] = 2 * kappa * xw[ucnt];
        out.residual[si] = sr.residual;
        out.failed[si] = 0;
        out.signed_row[si] = 1;
        out.negative[si] = sr.negative;
      };
      solve_row();
      if (length != 1) {
        for (std::size_t j = 0; j < ucnt; ++j) v[j] *= volume_unit;
        if (walls && opt.wall.rows[si]) out.wall_flux[si] /= length;
      }
    }
  }
  check_interrupt();  // rows skipped after a stop request: the volumes are incomplete
  return out;
}

}  // namespace vrsph
