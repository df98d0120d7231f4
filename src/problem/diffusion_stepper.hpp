// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the time loop of diffuse() (diffusion.cpp) on a DiffusionOperator: explicit Euler
// (with the Neumann block solved after each step), backward Euler and Crank–Nicolson, the
// error history and the divergence test. Each rank steps its owned particles; the halo is
// refreshed from the owners before every use of the stencils (serial: nothing to refresh).
#include <memory>
#include "diffusion_operator.hpp"

namespace vrsph::detail {

class DiffusionStepper {
 public:
  /// Sets up the implicit matrix or the explicit scheme's Neumann block once (a PreparedSolver).
  DiffusionStepper(const DiffusionOperator& op, const DiffusionProblem& p, const DiffusionOptions& o,
                   DiffusionResult& r);
  /// From u0 at t = 0 to t_end (or to the step at which the solution diverged).
  void run(DiffusionResult& r);
  /// The local particles' values (owned and halo).
  const Field& u() const { return u_; }

 private:
  Real source(Index i, Real t) const;
  Real owned_max(const Field& v, const std::vector<char>& where) const;
  void record(Real t, DiffusionResult& r) const;
  void explicit_step(Real t, Real t_next, DiffusionResult& r);
  void neumann_values(Real t_next, DiffusionResult& r);
  void implicit_step(Real t, Real t_next, DiffusionResult& r);
  void solve_step(const Eigen::VectorXd& rhs, Eigen::VectorXd& x, Real t_next, DiffusionResult& r) const;
  bool diverged(Real t, DiffusionResult& r);

  const DiffusionOperator& op_;
  const DiffusionProblem& p_;
  const DiffusionOptions& o_;
  const PointCloud& cloud_;
  const Communicator& comm_;
  Field u_;
  Real theta_ = 1;
  std::unique_ptr<PreparedSolver> solver_;
  NeumannBlock block_;
  std::vector<char> known_;  ///< per local particle: not an unknown
  Real data_scale_ = 0, source_scale_ = 0;
};

}  // namespace vrsph::detail
