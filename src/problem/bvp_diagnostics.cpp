// SPDX-License-Identifier: BSD-3-Clause
// Stage 6 of the solve pipeline (bvp_pipeline.hpp): what the operator rows say before they
// are solved — infeasible local problems, conditioning, overflow, negative weights and the
// M-matrix property — over every rank, rows named by their global numbers.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/properties.hpp>
#include "bvp_pipeline.hpp"
#include "transmissibilities.hpp"

namespace vrsph::detail {

namespace {
// Every infeasible row of every rank, worst first, and one warning line for them (or the
// error, with InfeasiblePolicy::Error).
void report_infeasible(const Partition& part, const LocalResidualSummary& local, const char* what,
                       const BvpSolveOptions& o, BvpSolution& s) {
  const Communicator& comm = part.comm();
  s.max_local_residual = std::max(s.max_local_residual, max_over_ranks(comm, local.max_relative));
  const long long count = sum_over_ranks(comm, static_cast<long long>(local.infeasible));
  s.infeasible += static_cast<Index>(count);
  if (count == 0) return;
  std::vector<double> mine;  // (residual, global id) pairs; ids are exact in a double below 2^53
  for (const auto& [residual, i] : local.worst) {
    mine.push_back(residual);
    mine.push_back(static_cast<double>(part.global_id(i)));
  }
  const std::vector<double> all = gather_over_ranks(comm, mine);
  std::vector<std::pair<Real, Index>> rows;
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) rows.emplace_back(all[k], static_cast<Index>(all[k + 1]));
  std::stable_sort(rows.begin(), rows.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (const auto& [residual, id] : rows) {
    s.infeasible_particles.push_back(id);
    s.infeasible_residuals.push_back(residual);
  }
  const Real worst = rows.empty() ? std::numeric_limits<Real>::quiet_NaN() : rows[0].first;
  const long long worst_id = rows.empty() ? -1 : rows[0].second;
  const std::string msg = infeasible_rows_warning(label_of(o), count, what, worst, worst_id, o.infeasible_tolerance);
  if (o.on_infeasible == InfeasiblePolicy::Error) throw NumericalError(msg);
  s.warnings.push_back(msg);
}

// A coefficient near the floating-point range (1e300) overflows the weights: said here
// rather than left to the solver's NaN residual.
void check_finite_rows(const Partition& part, const Stencil& L, const std::vector<char>& rows, const BvpSolveOptions& o) {
  const PointCloud& cloud = part.local();
  for (Index i = 0; i < cloud.size(); ++i) {
    if (!rows[static_cast<std::size_t>(i)]) continue;
    for (Index k = L.row_begin(i); k < L.row_end(i); ++k)
      if (!std::isfinite(L.values[0][static_cast<std::size_t>(k)])) {
        const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
        throw NumericalError(concat(label_of(o), ": the stencil row of particle ", part.global_id(i), " (", x[0], ", ",
                                    x[1], ", ", x[2], ") is not finite: the coefficient or mobility (or 1/h^2) "
                                    "overflows; rescale the problem"));
      }
  }
}

// Negative off-diagonal weights, rows with negative volumes and [SPE] ξ, over every rank.
void report_transmissibilities(const Partition& part, const Method& method, const Stencil& L,
                               const std::vector<char>& rows, const BvpSolveOptions& o, BvpSolution& s) {
  const Communicator& comm = part.comm();
  summarise_transmissibilities(L, rows, s);  // this rank's rows, then over the ranks
  s.signed_rows = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(s.signed_rows)));
  const Real xi = max_over_ranks(comm, std::isnan(s.xi_max) ? -std::numeric_limits<Real>::infinity() : s.xi_max);
  s.xi_max = std::isfinite(xi) ? xi : std::nan("");
  s.negative_transmissibilities =
      static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(s.negative_transmissibilities)));
  for (Index& i : s.negative_rows) i = static_cast<Index>(part.global_id(i));
  if (s.signed_rows > 0) {
    s.warnings.push_back(signed_rows_warning(label_of(o), s));
  } else if (method.info().monotone && s.negative_transmissibilities > 0) {
    std::string first;  // this rank's first rows
    for (std::size_t k = 0; k < s.negative_rows.size(); ++k) first += concat(k ? ", " : "", s.negative_rows[k]);
    s.warnings.push_back(concat(label_of(o), ": ", s.negative_transmissibilities, " negative off-diagonal weight(s) "
                                "in interior rows of a scheme meant to be monotone: the maximum principle does not "
                                "hold there (strong anisotropy or disorder; [SPE] (92)/(93), xi_max = ", s.xi_max,
                                "); first rows: ", first));
  }
}

// Rows: the owned unknown rows without flux rows; columns: every unknown, halo copies
// included; the chains to a strictly dominant row (or to `chain_anchor`) followed over the ranks.
void report_m_matrix(const Partition& part, const OperatorRows& r, const RowMasks& masks, const LocalData& data,
                     Index chain_anchor, BvpSolution& s) {
  const bool flux_rows_apart = s.neumann_particles > 0 && !r.balance;
  const std::vector<char>& rows = flux_rows_apart ? masks.interior : masks.unknown;
  const std::vector<char> columns = flux_rows_apart ? tag_mask(part.local(), {Tag::Interior}) : masks.unknown_columns;
  const std::optional<Stencil> robin_rows = with_robin_diagonal(r.L, masks.flux, data.robin);
  const MMatrixReport mm = check_m_matrix(robin_rows ? *robin_rows : r.L, columns, 1e-12, rows,
                                          [&](std::span<const Index> off, std::span<const Index> tgt, std::vector<char> seeds) {
                                            if (chain_anchor >= 0) seeds[static_cast<std::size_t>(chain_anchor)] = 1;
                                            return part.reach(off, tgt, std::move(seeds));
                                          });
  const Communicator& comm = part.comm();
  const bool z = all_ranks(comm, mm.z_matrix), dd = all_ranks(comm, mm.diagonally_dominant),
             chained = all_ranks(comm, mm.chained);
  s.m_matrix = z && dd && chained;
  if (!part.distributed()) {
    s.m_matrix_summary = mm.summary();
    return;
  }
  const long long rows_total = sum_over_ranks(comm, static_cast<long long>(mm.rows));
  s.m_matrix_summary = s.m_matrix ? concat("-L is an M-matrix (", rows_total, " unknown rows on ", comm.size(),
                                           " ranks, weakly chained diagonally dominant)")
                                  : concat("-L is NOT an M-matrix:", z ? "" : " off-diagonal entries of the wrong sign;",
                                           dd ? "" : " rows not diagonally dominant;",
                                           chained ? "" : " rows not connected to a strictly dominant (boundary) row;",
                                           " (", comm.size(), " ranks)");
}
}  // namespace

void diagnose_rows(const Partition& part, const Method& method, const OperatorRows& r, const RowMasks& masks,
                   const LocalData& data, Index chain_anchor, const BvpSolveOptions& o, BvpSolution& s) {
  const auto all = static_cast<std::size_t>(part.local_size());
  collective(part.comm(), [&] {
    report_infeasible(part, summarise_local_residuals(r.L, masks.interior, o.infeasible_tolerance, all), "interior", o, s);
    if (s.neumann_particles > 0)
      report_infeasible(part, summarise_local_residuals(r.balance ? r.L : r.G, masks.flux, o.infeasible_tolerance, all),
                        r.balance ? "Neumann (balance)" : "Neumann", o, s);
  });
  Real condition = 0;
  for (std::size_t i = 0; i < all; ++i) {
    if (masks.interior[i] && !r.L.condition.empty()) condition = std::max(condition, r.L.condition[i]);
    if (masks.flux[i] && !r.G.condition.empty()) condition = std::max(condition, r.G.condition[i]);
  }
  s.condition_max = max_over_ranks(part.comm(), condition);
  collective(part.comm(), [&] { check_finite_rows(part, r.L, r.rows(masks), o); });
  report_transmissibilities(part, method, r.L, r.rows(masks), o, s);
  if (o.check_m_matrix) report_m_matrix(part, r, masks, data, chain_anchor, s);
}

}  // namespace vrsph::detail
