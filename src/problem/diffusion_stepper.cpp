// SPDX-License-Identifier: BSD-3-Clause
// The time loop of diffuse() (diffusion_stepper.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/stencil/apply.hpp>
#include "diffusion_stepper.hpp"

namespace vrsph::detail {

DiffusionStepper::DiffusionStepper(const DiffusionOperator& op, const DiffusionProblem& p, const DiffusionOptions& o,
                                   DiffusionResult& r)
    : op_(op), p_(p), o_(o), cloud_(op.part->local()), comm_(op.part->comm()) {
  u_ = op.part->to_local(p.u0);
  known_.resize(static_cast<std::size_t>(cloud_.size()));
  for (std::size_t i = 0; i < known_.size(); ++i) known_[i] = !op.masks.unknown_columns[i];
  // Implicit schemes: I - θ dt A on the interior rows, the flux rows as they are (they hold at
  // every time), set up once (factorised, or its preconditioner built) and reused. Explicit
  // scheme with Neumann particles: after each step the flux rows are solved for the Neumann
  // values, the block A_NN set up once.
  theta_ = o.scheme == TimeScheme::Implicit ? 1.0 : 0.5;
  SolverOptions so = o.solver;
  so.communicator = comm_;
  if (so.dimension == 0) so.dimension = cloud_.dim;
  so.reused_setup = true;  // one set-up for every step
  if (o.scheme != TimeScheme::Explicit) {
    solver_ = std::make_unique<PreparedSolver>(implicit_matrix(op, theta_, o.dt), so);
  } else if (op.neumann) {
    block_ = neumann_block(op);
    // The block has the boundary's size (N^((d-1)/d) rows) and is factorised once: a direct
    // solve, as serial `auto` picks at that size. Under MPI it is PETSc's MUMPS: a Krylov
    // solve of this block stopped in PETSc's communication set-up (PetscCommBuildTwoSided,
    // error 162) on 2 ranks, not understood yet (docs/parallel.md).
    if (comm_.distributed())
      so.petsc_options = "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps " + so.petsc_options;
    solver_ = std::make_unique<PreparedSolver>(block_.A, so);
  }
  if (solver_) {
    r.solver = solver_->solver();
    r.seconds_factorisation = solver_->seconds_setup();
  }
}

Real DiffusionStepper::source(Index i, Real t) const {
  return p_.source ? p_.source(cloud_.positions[static_cast<std::size_t>(i)], t) : 0.0;
}

// max |v_i| over the particles marked in `where`, over every rank.
Real DiffusionStepper::owned_max(const Field& v, const std::vector<char>& where) const {
  Real m = 0;
  for (Index i = 0; i < v.size(); ++i)
    if (where[static_cast<std::size_t>(i)]) m = std::max(m, std::abs(v[i]));
  return max_over_ranks(comm_, m);
}

void DiffusionStepper::record(Real t, DiffusionResult& r) const {
  if (o_.on_step) o_.on_step(t, op_.part->to_chunk(u_));
  if (!p_.exact) return;
  Real e = 0;
  for (Index i = 0; i < u_.size(); ++i)
    if (op_.masks.unknown[static_cast<std::size_t>(i)])
      e = std::max(e, std::abs(u_[i] - p_.exact(cloud_.positions[static_cast<std::size_t>(i)], t)));
  e = max_over_ranks(comm_, e);
  r.times.push_back(t);
  r.error_inf.push_back(all_ranks(comm_, std::isfinite(u_.sum())) ? e : std::numeric_limits<Real>::infinity());
}

void DiffusionStepper::solve_step(const Eigen::VectorXd& rhs, Eigen::VectorXd& x, Real t_next, DiffusionResult& r) const {
  const SolveReport rep = solver_->solve(rhs, x);
  collective(comm_, [&] {
    check<NumericalError>(rep.success, "the ", to_string(o_.scheme), " step at t = ", t_next, " failed: ", rep.solver,
                          ": ", rep.message, " (relative residual ", rep.residual, ")");
  });
  r.solver_iterations += rep.iterations;
}

void DiffusionStepper::explicit_step(Real t, Real t_next, DiffusionResult& r) {
  const Field Lu = apply_component(op_.L, u_, 0);
  for (Index i = 0; i < u_.size(); ++i)
    if (op_.masks.interior[static_cast<std::size_t>(i)]) u_[i] += o_.dt * (Lu[i] + source(i, t));
  if (op_.neumann) neumann_values(t_next, r);
}

// A_NN u_N = q(t+) - c(t+) - A_NI u_I(t+): the flux rows solved for the Neumann values.
void DiffusionStepper::neumann_values(Real t_next, DiffusionResult& r) {
  op_.part->update_halo(u_);  // the interior values just stepped, at the halo too
  Field with_data = u_;
  set_dirichlet_values(op_, p_, t_next, with_data);
  const Eigen::VectorXd c_next = known_coupling(op_, p_, t_next);
  const LinearSystem& sys = op_.local;
  const auto rows = static_cast<Index>(block_.dofs.size());
  Eigen::VectorXd rhs(rows), x(rows);
  for (Index k = 0; k < rows; ++k) {
    const Index d = block_.dofs[static_cast<std::size_t>(k)];
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    Real interior_part = 0;
    for (CsrMatrix::InnerIterator it(sys.A, d); it; ++it) {
      const Index j = sys.particle_of_dof[static_cast<std::size_t>(it.col())];
      if (block_.block_of[static_cast<std::size_t>(j)] < 0) interior_part += it.value() * with_data[j];
    }
    rhs[k] = p_.flux(cloud_.positions[static_cast<std::size_t>(i)], t_next) - c_next[d] - interior_part;
    x[k] = u_[i];
  }
  solve_step(rhs, x, t_next, r);
  for (Index k = 0; k < rows; ++k) u_[sys.particle_of_dof[static_cast<std::size_t>(block_.dofs[static_cast<std::size_t>(k)])]] = x[k];
}

void DiffusionStepper::implicit_step(Real t, Real t_next, DiffusionResult& r) {
  const LinearSystem& sys = op_.local;  // local columns: owned dofs, then the halo's
  const Index m = op_.owned_dofs();
  Eigen::VectorXd uU(sys.size()), rhs(m);
  for (Index d = 0; d < sys.size(); ++d) uU[d] = u_[sys.particle_of_dof[static_cast<std::size_t>(d)]];
  const Eigen::VectorXd c_next = known_coupling(op_, p_, t_next);
  for (Index d = 0; d < m; ++d) {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    rhs[d] = op_.is_flux_dof(d) ? p_.flux(cloud_.positions[static_cast<std::size_t>(i)], t_next) - c_next[d]
                                : uU[d] + theta_ * o_.dt * (source(i, t_next) + c_next[d]);
  }
  if (o_.scheme == TimeScheme::CrankNicolson) {
    const Eigen::VectorXd Au = sys.A * uU, c_now = known_coupling(op_, p_, t);
    for (Index d = 0; d < m; ++d) {
      if (op_.is_flux_dof(d)) continue;
      const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
      rhs[d] += 0.5 * o_.dt * (Au[d] + source(i, t) + c_now[d]);
    }
  }
  Eigen::VectorXd x = uU.head(m);  // the previous step: the initial guess of iterative solvers
  solve_step(rhs, x, t_next, r);
  for (Index d = 0; d < m; ++d) u_[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
}

// Divergence: not finite, or 1e8 times larger than anything the data explain (the initial
// values, the Dirichlet values so far, and the source integrated over time).
bool DiffusionStepper::diverged(Real t, DiffusionResult& r) {
  data_scale_ = std::max(data_scale_, owned_max(u_, known_));
  const bool finite = all_ranks(comm_, u_.allFinite());
  if (finite && max_over_ranks(comm_, u_.size() ? u_.cwiseAbs().maxCoeff() : 0.0) <= 1e8 * (1 + data_scale_ + source_scale_ * t))
    return false;
  r.diverged = true;
  r.warnings.push_back(concat("the solution ", finite ? "grew beyond 1e8 times its data" : "is no longer finite",
                              " at t = ", t, " (step ", r.steps, "): ",
                              o_.scheme == TimeScheme::Explicit
                                  ? concat("the explicit scheme is unstable at nu = ", r.nu)
                                  : std::string("the spatial operator with these boundary rows has growing modes (not "
                                                "dissipative), which implicit steps do not damp")));
  return true;
}

void DiffusionStepper::run(DiffusionResult& r) {
  set_dirichlet_values(op_, p_, 0, u_);
  record(0, r);
  const auto steps = static_cast<Index>(std::ceil(o_.t_end / o_.dt - 1e-9));
  const Real u0_max = max_over_ranks(comm_, p_.u0.size() ? p_.u0.cwiseAbs().maxCoeff() : 0.0);
  data_scale_ = std::max(owned_max(u_, known_), u0_max);
  Real s0 = 0;
  for (Index i = 0; i < u_.size(); ++i)
    if (op_.masks.interior[static_cast<std::size_t>(i)]) s0 = std::max(s0, std::abs(source(i, 0)));
  source_scale_ = max_over_ranks(comm_, s0);
  double stepping = 0;
  Real t = 0;
  for (Index step = 0; step < steps; ++step) {
    Stopwatch step_watch;
    const Real t_next = o_.dt * static_cast<Real>(step + 1);
    op_.part->update_halo(u_);  // owners' values of the last step at the halo
    if (o_.scheme == TimeScheme::Explicit) explicit_step(t, t_next, r);
    else implicit_step(t, t_next, r);
    t = t_next;
    set_dirichlet_values(op_, p_, t, u_);
    stepping += step_watch.seconds();
    ++r.steps;
    record(t, r);
    if (diverged(t, r)) break;
    if (o_.progress && (step % 64 == 0 || step + 1 == steps)) o_.progress(t / o_.t_end);
  }
  r.seconds_per_step = r.steps ? max_over_ranks(comm_, stepping) / static_cast<double>(r.steps) : 0;
}

}  // namespace vrsph::detail
