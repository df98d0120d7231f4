// SPDX-License-Identifier: BSD-3-Clause
// A fully periodic box without boundary particles (bvp_pipeline.hpp): -L is singular, its
// null space the constants. The solve pins one particle p (its row replaced by u_p = g_p)
// and the pinned system is an M-matrix for a monotone method. But the data are compatible
// with L only up to round-off and truncation: the equation dropped at p is then violated by
// some ρ, which acts as a point source at p and spoils the error around it (3D VRSPH
// compact rows, n = 24: max error 1.0e-2 against 5.0e-3 at n = 16). Here that defect is
// spread evenly instead: with z solving the pinned system for a unit source (z_p = 0),
// u = u1 - (ρ/σ) z satisfies L u = F - λ at every particle, λ = ρ/σ one constant (σ: the
// dropped equation's defect for z). One more solve with the same matrix. Under MPI the rank
// that owns p evaluates the defects (its row's columns are its owned and halo particles) and
// every rank takes part in the solves.
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/stencil.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph::detail {

using vrsph::detail::concat;

PinnedRow pinned_row(const Stencil& L, const LocalData& data, Index p) {
  PinnedRow r;
  if (p < 0) return r;  // another rank's
  r.particle = p;
  const Field& f = data.f();
  r.rhs = L.rhs.empty() ? f[p] : 0.0;
  for (Index k = L.row_begin(p); k < L.row_end(p); ++k) {
    const auto sk = static_cast<std::size_t>(k);
    const Index j = L.col[sk];
    r.entries.emplace_back(j, L.values[0][sk]);
    if (!L.rhs.empty()) r.rhs += L.rhs[sk] * f[j];
  }
  return r;
}

namespace {
// The dropped equation's defect L_p u - rhs for a solution over the owned dofs, on every rank
// (collective): the halo (a periodic box's images too) takes its owners' values first.
Real defect(const Partition& part, const PinnedRow& row, const LinearSystem& sys, const Eigen::VectorXd& x, Real rhs) {
  const Index m = sys.rows_owned >= 0 ? sys.rows_owned : sys.size();
  Field u = sys.known;
  for (Index d = 0; d < m; ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
  part.update_halo(u);
  Real s = 0;
  if (row.particle >= 0) {
    s = -rhs;
    for (const auto& [j, w] : row.entries) s += w * u[j];
  }
  return sum_over_ranks(part.comm(), s);  // only the pinning rank's is not zero
}
}  // namespace

void spread_periodic_defect(const Partition& part, LinearSystem& sys, const PinnedRow& row, const Field& f_owned,
                            const BvpSolveOptions& o, Eigen::VectorXd& x, BvpSolution& s) {
  if (!any_rank(part.comm(), row.particle >= 0)) return;
  const Real rho = defect(part, row, sys, x, row.rhs);
  Eigen::VectorXd unit = Eigen::VectorXd::Ones(sys.b.size());
  const Index m = sys.rows_owned >= 0 ? sys.rows_owned : sys.size();
  for (Index d = 0; d < m; ++d)
    if (sys.particle_of_dof[static_cast<std::size_t>(d)] == row.particle) unit[d] = 0;  // z_p = 0
  std::swap(sys.b, unit);
  BvpSolution second;
  const Eigen::VectorXd z = solve_system(part, sys, o, second);
  std::swap(sys.b, unit);
  const Real sigma = defect(part, row, sys, z, 1.0);
  check<NumericalError>(std::isfinite(sigma) && sigma != 0, "periodic solve: the unit source leaves no defect at the "
                        "pinned particle (sigma = ", sigma, "); the operator rows do not sum to a consistent Laplacian");
  const Real lambda = rho / sigma;
  x -= lambda * z;
  // λ is the constant the solve took out of the source: truncation-sized for compatible
  // data, larger when f does not integrate to zero.
  const Real mean_abs = sum_over_ranks(part.comm(), f_owned.cwiseAbs().sum()) /
                       static_cast<Real>(std::max<Index>(part.global_size(), 1));
  if (std::abs(lambda) > 0.05 * mean_abs)
    s.warnings.push_back(concat("fully periodic problem: the source's mean, ", lambda, " (", std::abs(lambda) / mean_abs,
                                " of the mean |f|), was removed to make it solvable (f must integrate to zero over "
                                "a period); check f"));
  s.periodic_source_shift = lambda;
  s.seconds_solve += second.seconds_solve;
  s.solve.iterations += second.solve.iterations;
  s.solve.seconds += second.solve.seconds;
}

}  // namespace vrsph::detail
