// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Time-dependent diffusion on a point cloud (issue 11; [SPE] §4.4, METHODS §3.7.9):
//   ∂u/∂t = div(a grad u) + s(x, t)   (or div(M grad u) with a diagonal mobility)
//   u = g(x, t) on Dirichlet particles, u(x, 0) = u0,
// with the method's div(a grad) stencil L on the interior particles, and one of
//   explicit  u^{n+1} = u^n + Δt (L u^n + s^n)                         (stable for ν <= ~0.25)
//   implicit  (I - Δt L) u^{n+1} = u^n + Δt s^{n+1}                    (backward Euler, 1st order)
//   cn        (I - Δt/2 L) u^{n+1} = (I + Δt/2 L) u^n + Δt/2 (s^n + s^{n+1})  (Crank–Nicolson, 2nd order)
// where the Dirichlet neighbours enter L u with their values at the time of the term. The
// implicit matrix is set up once (a PreparedSolver: sparse LU for small systems, PETSc
// GMRES + BoomerAMG for large ones under `auto`) and reused at every step, the previous
// step being the initial guess of an iterative solver.
//
// Stability number ν = Δt max(a) / ℓ_min² (METHODS §3.7.9: Δt/(Re h̃²_min), ℓ the kernel's
// smoothing length, the support over the kernel's support-per-smoothing-length ratio). The
// explicit scheme refuses ν above `nu_limit` (default 0.25, the bound [SPE] Table 1 reports),
// and a Δt above 2/ρ(L) measured on the operator (DiffusionResult::dt_limit), unless
// allow_unstable, which runs it anyway with a warning (the stability study).
// Neumann particles carry the flux row n·M (G u) = q(x, t) of the method's gradient G at
// every time (as in the steady solve): implicit schemes solve it with the step, the
// explicit one solves the Neumann block after each step.
#include <functional>
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

enum class TimeScheme { Explicit, Implicit, CrankNicolson };
/// "explicit" | "implicit" | "cn"; throws ConfigError otherwise.
TimeScheme parse_time_scheme(const std::string& name);
std::string to_string(TimeScheme s);

using SpaceTimeFunction = std::function<Real(const Vec3& x, Real t)>;

struct DiffusionProblem {
  PointCloud cloud;
  Field a;                   ///< coefficient > 0 at every particle (empty: 1)
  Eigen::MatrixXd mobility;  ///< or a diagonal mobility (N x dim)
  SpaceTimeFunction source;    ///< s(x, t) (empty: 0)
  SpaceTimeFunction boundary;  ///< g(x, t) at Dirichlet particles (required with Dirichlet particles)
  SpaceTimeFunction flux;      ///< q(x, t) = n·M grad u at Neumann particles (required with Neumann particles)
  Field u0;                    ///< initial values at every particle
  SpaceTimeFunction exact;     ///< optional: errors against it
};

struct DiffusionOptions {
  std::string method = "m-sph";
  MethodOptions method_options;
  KernelType kernel = KernelType::CubicSplineSPE;
  Real h_factor = 2.002;  ///< support radius / dx
  Real spacing = 0;       ///< dx (0: cloud.spacing, else estimated)
  TimeScheme scheme = TimeScheme::Explicit;
  Real dt = 0;            ///< time step (> 0)
  Real t_end = 1;
  Real nu_limit = 0.25;
  bool allow_unstable = false;
  SolverOptions solver;    ///< implicit schemes (auto: direct when small, else PETSc AMG)
  std::vector<Real> report_times;  ///< errors reported at these times (cubic interpolation between steps)
  /// Called at the start and after every step with (t, u at every particle).
  std::function<void(Real, const Field&)> on_step;
  std::function<void(double)> progress;  ///< fraction of t_end done
  /// The ranks to run on (default: serial). Distributed: each rank passes its part of the
  /// cloud and of a, the mobility and u0 in the problem (the functions are the same on every
  /// rank) and gets u (and on_step's field) for exactly those particles; on_step and
  /// progress are called on every rank; errors and timings are over every rank.
  Communicator communicator;
};

struct DiffusionResult {
  Field u;                      ///< at t_end (under MPI: at this rank's particles)
  Index steps = 0;
  Real dt = 0, nu = 0, smoothing_length_min = 0;
  /// Explicit scheme: 2 / ρ, ρ the largest |eigenvalue| of L over the interior rows (power
  /// iteration); a step above it (2 % margin) is refused like ν above nu_limit. 0 otherwise.
  Real dt_limit = 0;
  std::vector<Real> times;      ///< t_0 = 0, t_1, ... (with an exact solution)
  std::vector<Real> error_inf;  ///< max over the unknowns (interior, Neumann) of |u - exact| at each time
  std::vector<Real> report_error;  ///< at DiffusionOptions::report_times
  bool diverged = false;        ///< the solution stopped being finite (an unstable explicit run)
  std::vector<std::string> warnings;
  Index particles = 0;              ///< over every rank
  double seconds = 0;               ///< the whole run (with the error evaluations)
  double seconds_setup = 0;         ///< neighbours, stencil, assembly and the factorisation
  std::string solver;               ///< implicit schemes: what solves I - θ Δt L
  long long solver_iterations = 0;  ///< summed over the steps (1 per step for a direct solver)
  double seconds_factorisation = 0; ///< implicit schemes: the set-up of I - θ Δt L (LU or AMG), done once
  double seconds_per_step = 0;      ///< one time step (right-hand side, solve, boundary values)
};

/// Particles begin..end-1 of a problem with their a, mobility and u0 (the functions shared):
/// one rank's part for a distributed run.
DiffusionProblem part_of(const DiffusionProblem& problem, Index begin, Index end);

/// Throws ConfigError (dt <= 0, t_end <= 0, an unstable explicit step without allow_unstable,
/// a method without a gradient for Neumann rows), InputError (sizes, data that are not finite), NumericalError (a failed
/// factorisation).
DiffusionResult diffuse(const DiffusionProblem& problem, const DiffusionOptions& options);

}  // namespace vrsph
