// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One call from a point cloud to the solution of div(a grad u) = f:
//
//   BoundaryValueProblem p{cloud};            // tags: interior / dirichlet / neumann / ghost
//   p.f = ...; p.g = ...; p.q = ...;          // values at every particle (Field)
//   BvpSolution s = solve(p, {.method = "vrsph"});
//   s.u                                       // the solution at every particle
//
// The pipeline: smoothing radius -> neighbours -> the method's div(a grad) stencil on
// the interior rows and its gradient on the Neumann rows -> flux rows -> assembly ->
// linear solve, with every diagnostic the studies report. The studies are loops over
// this call.
//
// Sign convention: the PDE is div(a grad u) = f (for the Poisson equation -Δu = s give
// f = -s). Neumann data are the outward flux q = a ∂u/∂n at Neumann particles, whose
// `normals` must be outward unit normals. Dirichlet particles carry u = g. Ghost
// particles are neither unknowns nor data.
#include <cmath>
#include <string>
#include <vector>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/solve/solver.hpp>
#include <vrsph/stencil/properties.hpp>

namespace vrsph {

enum class InfeasiblePolicy { Warn, Error };
/// "warn" or "error"; throws ConfigError otherwise.
InfeasiblePolicy parse_infeasible_policy(const std::string& name);

struct BoundaryValueProblem {
  PointCloud cloud;
  Field a;                 ///< coefficient a > 0 at every particle (empty: a = 1)
  /// Diagonal tensor mobility M = diag(m_1..m_d) (N x dim, m_k > 0) in place of a: the PDE
  /// is div(M grad u) = f and the Neumann data are q = n·M grad u. Empty: scalar a. Only
  /// methods with MethodInfo::tensor_mobility take it (the [SPE] schemes).
  Eigen::MatrixXd mobility;
  Eigen::MatrixXd grad_a;  ///< optional exact grad a (N x dim) for the Taylor-type methods
  Field f;                 ///< right-hand side at every particle (read at interior particles)
  Field g;                 ///< Dirichlet values (read at Dirichlet particles and at the pinned one)
  Field q;                 ///< Neumann flux a ∂u/∂n (read at Neumann particles; empty if none)
  /// Robin coefficient β >= 0 at every particle (empty: none): Neumann particles with β > 0
  /// carry a ∂u/∂n + β u = q (q then includes β u).
  Field robin;
  /// Only Neumann data: the solution is fixed up to a constant; pin this unknown to g
  /// (-1: none; fix_constant picks the interior particle nearest the centroid).
  Index pinned = -1;
  bool fix_constant = false;
};

struct BvpSolveOptions {
  std::string method = "vrsph";
  MethodOptions method_options;
  KernelType kernel = KernelType::CubicSpline;
  /// Support radius: h > 0 is used as given; otherwise h_factor x spacing by h_mode
  /// (fixed: kappa dx; covering: kappa max(dx, r_N); knn: per particle).
  Real h = 0;
  Real h_factor = 3;
  SmoothingMode h_mode = SmoothingMode::Fixed;
  int h_knn = 0;
  /// Particle spacing dx (0: cloud.spacing, else estimate_spacing(cloud)).
  Real spacing = 0;
  SolverOptions solver;
  InfeasiblePolicy on_infeasible = InfeasiblePolicy::Warn;
  Real infeasible_tolerance = 1e-6;  ///< local residual / |b| above this = infeasible
  bool check_m_matrix = true;
  std::string label;                 ///< prefix of warning messages (e.g. "vrsph n=40 seed=1")
  /// Measure each stage's peak resident memory (BvpSolution::stage_peak_bytes); it resets
  /// the process's peak counter, so the process-wide peak is lost.
  bool measure_memory = false;
  /// Keep the interior operator rows and the assembled system in the solution
  /// (BvpSolution::operator_rows, ::system): boundary fluxes and solver studies need them.
  bool keep_matrices = false;
  /// The ranks to solve on. Distributed (more than one rank): each rank passes its own part
  /// of the cloud and of the data in `problem` (any split; the particles' global numbering is
  /// the chunks in rank order) and gets u for exactly those particles, in the same order.
  /// The particles are re-partitioned along a Morton curve with halos (DistributedCloud),
  /// stencils are built for owned rows only and the system is solved by PETSc (MPIAIJ); the
  /// result equals the serial one up to the solver's tolerance. Needs h_mode fixed (or h),
  /// and a spacing (given, cloud.spacing, or from a known domain); `pinned` is not
  /// supported (fix_constant is). Default: serial.
  Communicator communicator;
};

struct BvpSolution {
  Field u;                         ///< at every particle (data values at known particles)
  Index particles = 0, unknowns = 0, neumann_particles = 0;
  Real spacing = 0, h = 0;         ///< h: support radius (mean of per-particle radii in knn mode)
  Real covering_radius = 0;        ///< r_N when h_mode = covering
  Real neighbours_mean = 0, nnz_per_row = 0;
  Index infeasible = 0;            ///< rows whose local problem failed or exceeds the tolerance
  /// Every such row (global numbers under MPI), worst first, and its relative residual
  /// (infinity: the local solve failed); `warnings` holds one line for them.
  std::vector<Index> infeasible_particles;
  std::vector<Real> infeasible_residuals;
  Real max_local_residual = 0;
  Real condition_max = 0;          ///< largest local-system condition number (0: none)
  bool m_matrix = false;           ///< -L is an M-matrix on the unknowns' rows
  /// Off-diagonal entries L_ij < 0 in the interior rows (negative transmissibilities: the
  /// two-point-flux structure and the maximum principle are lost there), and the rows.
  Index negative_transmissibilities = 0;
  std::vector<Index> negative_rows;  ///< the first few interior particles with one
  /// Rows that took negative volumes to meet their moment conditions (VRSPH boundary=signed).
  Index signed_rows = 0;
  Real xi_max = std::nan("");       ///< [SPE](94) max over interior rows of max_J ξ_I·Δ_J (NaN: not an [SPE] scheme)
  std::string m_matrix_summary;
  SolveReport solve;
  Field local_residual;            ///< per particle (interior rows), zeros for methods without one
  /// Only Neumann data: |boundary flux - integral of f| relative to their size, by particle
  /// quadrature (first order; > 0.2 means the data violate the solvability condition,
  /// and a warning says so). The studies, which know the domain, check it exactly.
  Real neumann_imbalance = 0;
  /// Fully periodic problems: the constant λ taken out of f to make the data compatible with
  /// the discrete operator (L u = f - λ at every particle; truncation-sized for data with zero
  /// mean, and a warning when it is more than 5 % of the mean |f|).
  Real periodic_source_shift = 0;
  std::vector<std::string> warnings;
  /// seconds_neighbours: the support radius, the partition, the data's exchange and the search.
  double seconds_neighbours = 0, seconds_stencil = 0, seconds_assemble = 0, seconds_solve = 0;
  /// With BvpSolveOptions::measure_memory: peak resident bytes of the process during each
  /// stage (what the stage held plus what earlier stages still held).
  struct StagePeaks {
    std::size_t neighbours = 0, stencil = 0, assemble = 0, solve = 0;
  } stage_peak_bytes;
  /// With BvpSolveOptions::keep_matrices: the div(a grad) rows of the interior particles
  /// over every particle (other rows empty), and the linear system that was solved.
  /// Distributed: operator_rows is over the whole cloud's particle numbers (the chunks in
  /// rank order) and holds the rows this rank owned in the partition (each row on exactly
  /// one rank: the ranks' matrices sum to the serial one); system is this rank's rows.
  SparseMatrix operator_rows;
  LinearSystem system;
  /// Balance rows (VRSPH flux=balance): the wall flux c_i >= 0 of each Neumann particle's row,
  /// which approximates div(a grad u) - c_i (a du/dn)_i (0 elsewhere; empty without balance rows).
  Field wall_flux;
  /// Distributed solves: ranks and what the partition moved (this rank's figures; the
  /// maxima over ranks in the `_max` fields).
  struct Distribution {
    int ranks = 1;
    Index owned = 0, halo = 0;
    long long halo_bytes = 0, halo_bytes_max = 0, halo_bytes_total = 0, migration_bytes = 0;
    int halo_messages = 0;
    double seconds_distribute = 0;  ///< the partition's last build (a share of seconds_neighbours)
  } distribution;
};

/// Particles begin..end-1 of a problem with their data (every non-empty field cut alike):
/// one rank's part for a distributed solve.
BoundaryValueProblem part_of(const BoundaryValueProblem& problem, Index begin, Index end);

/// Masks over the particles: 1 where the tag is one of `tags`.
std::vector<char> tag_mask(const PointCloud& cloud, std::initializer_list<Tag> tags);
/// The unknowns of a boundary value problem: interior and Neumann particles.
std::vector<char> unknown_mask(const PointCloud& cloud);

/// Throws InputError (sizes, non-finite or non-positive data, Neumann particles without
/// normals, only Neumann data and nothing pinned), ConfigError (unknown method, method
/// without div-a-grad or, with Neumann particles, without a gradient), GeometryError
/// (particles without neighbours, unknowns not connected to data) and NumericalError
/// (a failed solve; infeasible local problems with InfeasiblePolicy::Error).
BvpSolution solve(const BoundaryValueProblem& problem, const BvpSolveOptions& options = {});

}  // namespace vrsph
