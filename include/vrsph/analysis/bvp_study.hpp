// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Boundary value problem studies: div(a grad u) = f in the box, u = g on the Dirichlet
// particles, for any registered method, over a refinement list and a set of seeds.
// Shared by `vrsph study`, `vrsph solve` and the reproduction tests.
//
// Problems:
//   qw-ex5   [QW] Example 5: [0,1]^d, u = prod sin(pi x_k),
//            a = 1 + |x|^2, f = a Δu + ∇a·∇u, g = 0; layout A with n intervals (dx = 1/n),
//            unknowns = interior particles. --dim 3 gives the 3D analogue.
//   aar-static  [AAR] §5 elastic static test: -u'' = e^x on
//            [0,1], u(0) = 0, u'(1) = 0 (traction-free end: Neumann particle), exact
//            u = -e^x + e x + 1; defaults: Gaussian kernel with l = dx (support 6 dx),
//            perturbation U(-dx/4, dx/4).
//   spe-dirichlet, spe-mixed  [SPE] §5 Laplace problems on the unit square (reproduce/spe_problems.hpp):
//            layout B, the [SPE] cubic spline with --h-factor = f (support 2 f dx), random
//            sets U(-0.1001 dx, 0.1001 dx); relative error (95) in error_rel.
//   qw-ex5 and custom are built in; the papers' problems (aar-static, spe-*) come from a
//   StudyProblemCatalogue, vrsph::published_problems() (reproduce/published_problems.hpp).
//   custom   [0,1]^d with user expressions u, a, f (and optionally g; default g = u), or a
//            diagonal mobility M = diag(m_1..m_d) (`mobility`, one expression per direction)
//            instead of a: f = div(M grad u), q = n·M grad u.
// Boundary conditions: boundary particles are Dirichlet (u = g) unless every box face
// they lie on is listed in `neumann` (faces x0, x1, y0, y1, z0, z1 or all): then they
// carry a flux row a ∂u/∂n = q built from the method's own gradient stencil (corner
// normal = normalised sum of the face normals, METHODS §4; Dirichlet–Neumann corners stay
// Dirichlet). q defaults to a ∇u·n of the exact solution.
// Cloud families: uniform, perturbed (interior particles U(-delta dx, delta dx)),
// centroids (CGAL mesh centroids + mesh nodes on the faces as Dirichlet particles), disk
// (ball inscribed in the box).
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include <vrsph/solve/solver.hpp>

namespace vrsph {

class ScalarFunction;
struct BvpStudyParams;

/// A named problem of a catalogue: its functions, the faces with flux rows unless the study
/// names others, and the support radius per h-factor (2 where the h-factor is a smoothing
/// length over dx, as [SPE]'s f).
struct StudyProblem {
  std::shared_ptr<const ScalarFunction> u, a, f, g;
  std::function<Real(const Vec3&, const Vec3&)> flux;  ///< q(x, outward normal); empty: a grad u . n
  std::vector<std::string> neumann;
  Real support_per_h_factor = 1;
};

/// Named problems beyond the built-in qw-ex5 and custom (a study stays free of any paper's
/// problem: the reproductions hand theirs in).
struct StudyProblemCatalogue {
  std::vector<std::string> names;
  std::function<StudyProblem(const BvpStudyParams&)> make;  ///< for a name of `names`; checks the params
  bool has(const std::string& name) const;
};

struct BvpStudyParams {
  std::string problem = "qw-ex5";  ///< qw-ex5 | custom | a name of `catalogue`
  StudyProblemCatalogue catalogue;  ///< e.g. published_problems() (reproduce/published_problems.hpp)
  int dim = 2;
  std::vector<std::string> methods{"vrsph"};
  std::map<std::string, MethodOptions> method_options;
  CloudFamily cloud = CloudFamily::Uniform;
  std::vector<int> n{20, 40, 80, 160};
  std::vector<std::uint64_t> seeds{1};
  Real h_factor = 3;                 ///< kappa in the smoothing rule (see h_mode)
  SmoothingMode h_mode = SmoothingMode::Fixed;
  int h_knn = 0;                     ///< k for SmoothingMode::Knn (0: 2d)
  Real delta = 0.5;
  bool perturb_boundary = false;     ///< also move boundary particles along their faces
  Real regular_layer = 0;            ///< first-layer particles move only tangentially (width in dx)
  KernelType kernel = KernelType::CubicSpline;
  SolverOptions solver;
  std::string u, a, f, g;            ///< custom problem: expressions or catalogue names
  std::vector<std::string> mobility; ///< custom problem: m_1..m_d (diagonal tensor), instead of a
  Layout layout = Layout::Vertex;    ///< layout A (vertex lattice) or B (cell centres + boundary particles)
  std::vector<std::string> neumann;  ///< Neumann faces (empty: the problem's default)
  /// Periodic axes of the unit box ("x,y", "all"; empty: none). Fully periodic: no boundary
  /// particles, u has zero mean and the errors are taken up to the constant.
  std::string periodic;
  std::string q;                     ///< Neumann data a ∂u/∂n (expression; default from u)
  /// Robin faces: flux rows a ∂u/∂n + β u = q with β = `beta` (expression >= 0); q defaults
  /// to a ∂u/∂n + β u of the exact solution. A face is Neumann or Robin, not both.
  std::vector<std::string> robin;
  std::string beta;
  bool fix_constant = false;         ///< pin the unknown nearest the centre to g (pure Neumann problems)
  InfeasiblePolicy on_infeasible = InfeasiblePolicy::Warn;
  Real infeasible_tolerance = 1e-6;  ///< local residual / |b| above this = infeasible
  bool check_m_matrix = true;
  bool measure_memory = false;       ///< per-stage peak memory in BvpRun (resets the process peak)
  /// MPI ranks to solve on (default serial). Distributed: every rank makes the cloud, keeps
  /// the slice [N r/P, N (r+1)/P) of it as its part, samples the data there and solves with
  /// the distributed pipeline (BvpSolveOptions::communicator); errors and diagnostics are
  /// reduced over the ranks, so every rank gets the serial table.
  Communicator communicator;
  std::function<void(const std::string&, double)> progress;
};

/// One (method, n, seed) solve.
struct BvpRun {
  std::string method;
  int n = 0;
  std::uint64_t seed = 0;
  Index particles = 0, unknowns = 0, neumann_particles = 0;
  Real dx = 0, h = 0;        ///< h: support radius (mean of per-particle radii in knn mode)
  Real covering_radius = 0;  ///< r_N when h_mode = covering
  ErrorReport errors;        ///< over the unknowns, |U_i - u(x_i)|
  /// [SPE](95): sqrt(Σ V_K ((U_K - u_K)/u_K)² / Σ V_K) over the interior particles (NaN if
  /// some u_K = 0); dof = their count ([SPE]'s DoF: n^d cells, Neumann particles not counted)
  Real error_rel = 0;
  Index dof = 0;
  Index negative_transmissibilities = 0;  ///< negative off-diagonal weights in interior rows
  Real xi_max = 0;                        ///< [SPE](94) max_J ξ_I·Δ_J over interior rows (NaN: not [SPE])
  bool m_matrix = false;
  std::string m_matrix_summary;
  Real neighbours_mean = 0, nnz_per_row = 0;
  Index infeasible = 0;      ///< rows whose local residual exceeds the tolerance (or failed)
  Real max_local_residual = 0;
  Real condition_max = 0;    ///< largest local-system condition number (Taylor-type methods; 0: none)
  std::vector<Index> infeasible_particles;  ///< every such row, worst first (BvpSolution)
  std::vector<Real> infeasible_residuals;
  SolveReport solve;
  double seconds_cloud = 0, seconds_neighbours = 0, seconds_stencil = 0, seconds_assemble = 0, seconds_solve = 0;
  double seconds_data = 0;  ///< sampling a, f, g, q and the exact u, and the error norms
  double peak_memory_mib = 0;  ///< peak resident memory of the process when this run ended (max over ranks)
  BvpSolution::Distribution distribution;  ///< ranks and halo traffic of a distributed run
  Index first_id = 0;          ///< global number of this rank's first particle (distributed runs)
  /// With BvpStudyParams::measure_memory: peak resident bytes during the cloud stage, and
  /// the solve's stages (BvpSolution::stage_peak_bytes).
  std::size_t peak_bytes_cloud = 0;
  std::size_t resident_bytes_before = 0;  ///< what the process held when the run started
  BvpSolution::StagePeaks stage_peak_bytes;
  // Fields for output (kept only when requested).
  Field U, exact, local_residual;
};

/// Mean over seeds of one (method, n).
struct BvpStudyRow {
  BvpRun first;              ///< the first seed's run (sizes, timings, diagnostics)
  int seeds = 1;
  Real error_inf = 0, error_inf_std = 0, error_l2 = 0;
  Real error_inf_min = 0, error_inf_max = 0;  ///< spread of the max-norm error over the seeds
  Real error_inf_interior = 0, error_inf_boundary = 0;
  Real order_inf = 0, order_l2 = 0;
  Real error_rel = 0, error_rel_std = 0, order_rel = 0;  ///< [SPE](95): mean, std over seeds, order in dx
  Index negative_transmissibilities_max = 0;              ///< over the seeds
  Real xi_max = 0;                                        ///< over the seeds
  bool m_matrix_all = true;  ///< every seed gave an M-matrix
  Index infeasible_max = 0;
};

struct BvpStudyResult {
  BvpStudyParams params;
  std::vector<BvpStudyRow> rows;
  std::map<std::string, Real> fitted_order_inf;
  std::vector<std::string> warnings;
};

/// Throws ConfigError/InputError/GeometryError for bad input, NumericalError for a failed
/// solve or (with InfeasiblePolicy::Error) infeasible local problems.
BvpStudyResult run_bvp_study(const BvpStudyParams& params);
/// Support radius over dx of the study: h_factor, times 2 for the [SPE] problems (f = l/dx).
Real support_factor(const BvpStudyParams& params);
/// The particles of the built-in cloud at n intervals (the disk's about), before it is made.
double study_particles(const BvpStudyParams& params, int n);
/// The study's largest run, after the checks run_bvp_study makes before its first run (the
/// parameters, and each run's memory: ConfigError, ResourceError): its particles (the
/// estimate of study_particles) and whether it solves with PETSc (petsc, or auto above the
/// direct limit).
struct StudySize {
  Index particles = 0;
  bool petsc = false;
};
StudySize checked_study_size(const BvpStudyParams& params);
/// A single solve; keep_fields fills U, exact and local_residual (distributed: this rank's
/// part, and cloud_out its particles, global numbers from BvpRun::first_id).
BvpRun run_bvp(const BvpStudyParams& params, const std::string& method, int n, std::uint64_t seed, bool keep_fields,
               std::vector<std::string>* warnings = nullptr, PointCloud* cloud_out = nullptr);
Table to_table(const BvpStudyResult& result);
Json metadata_json(const BvpStudyResult& result);

}  // namespace vrsph
