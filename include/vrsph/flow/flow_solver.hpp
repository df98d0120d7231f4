// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Incompressible Navier–Stokes on particles, ∂u/∂t + (u·∇)u = -∇p + ν∇²u + g (unit density),
// with one method's operators (docs/flow.md). The velocity is advanced by a Runge–Kutta scheme
// whose every stage rate carries its own pressure:
//
//   k(u) = f(u) - (u·G)u - G p   (Eulerian: a fixed cloud)
//   k(u) = f(u)          - G p   (Lagrangian: the particles move with u, their positions
//                                 integrated by the same scheme, the operators update()d at
//                                 every stage through the moving-particle path)
//   f(u) = ν L u + g,    L p = D (f(u) - (u·G)u)  (the pressure that keeps ∂u/∂t divergence-free)
//
// — with VRSPH's Laplacian that p is then corrected (L δ = D(k(u)), p += δ) so that the rate
// itself is divergence-free to the defect's order, L ≠ D G (FlowOptions::pressure_corrections) —
// and each step ends with the approximate projection of the new velocity (projection.hpp), which
// removes the divergence the stages left instead of letting it drift. Heun's RK2 and Shu–Osher's
// SSP-RK3 keep their order in time for the velocity (projecting the state at every stage instead
// was first order in time in the Lagrangian frame: docs/flow.md). The viscous term is explicit
// by default; FlowViscosity::Implicit takes it implicitly instead, by the IMEX Runge–Kutta
// schemes of Ascher, Ruuth & Spiteri (ARS(4,4,3) for RK3, ARS(2,2,2) for RK2;
// implicit_viscosity.hpp): each stage solves (I - a dt ν L) U = R, the rest of the rate
// (advection, pressure, body force) explicit with the same pressure per stage, and the time
// step is then limited by the explicit terms only. step() refuses a time step beyond the
// stability limits of the scheme (bounds from Gershgorin discs of the operators, below) unless
// FlowOptions::allow_unstable. Eulerian advection uses the
// gradient as it is, without upwinding: the viscosity of the Reynolds numbers measured damps what a
// non-skew gradient excites (docs/flow.md); a hyperviscosity is available, and a run that blows up
// is stopped with its step.
//
// Boundaries: periodic axes, and walls: particles tagged Dirichlet, with outward normals, whose
// velocity is prescribed (FlowOptions::wall_velocity: at rest, or sliding along themselves like
// a cavity's lid). The pressure's wall condition is the normal component of the momentum
// equation at the wall, n·∇p = n·(ν∇²u - (u·∇)u + g) (the wall does not accelerate), with the
// wall's ν∇²u from the gradient applied twice (its own Laplacian row would be one-sided); the
// projection's is n·∇φ = 0. In the Lagrangian frame the wall particles stay where they are (a
// sliding wall's velocity is a boundary value, not a motion), and the walls' pressure rows are
// extrapolated from the fluid instead (projection.hpp; as with a free surface), which keeps
// the moving fluid off the walls; give such walls a full support (several layers).
//
// Free surfaces (FlowOptions::free_surface): the fluid particles free_surface.hpp's detection
// flags (at the start and, Lagrangian, after every move) take p = 0 and φ = 0; the body force
// may be ramped in; the time step is further limited by the body force, dt <= 0.25 (dx/|g|)^½
// (a particle may not fall more than dx/8 from rest in a step). Shifting moves surface
// particles only along the surface (Lind et al. 2012).
#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vrsph/analysis/free_surface.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/implicit_viscosity.hpp>
#include <vrsph/flow/pressure_poisson.hpp>
#include <vrsph/flow/projection.hpp>
#include <vrsph/flow/shifting.hpp>
#include <vrsph/moving/operators.hpp>

namespace vrsph {

enum class FlowFrame { Eulerian, Lagrangian };
enum class FlowScheme { RK2, RK3 };
enum class FlowViscosity { Explicit, Implicit };
/// The acceleration a walls' extrapolated pressure rows carry from the water (projection.hpp),
/// with a free surface: Momentum, the momentum equation at a wall at rest, a = ν∇²u + g (the
/// wall's ν∇²u from the gradient applied twice); BodyForce, g alone (Adami, Hu & Adams 2012 for
/// walls at rest). Measured on the dam break (docs/free_surface.md): Momentum holds the surge's
/// thin front off the floor at nx = 40, BodyForce lets the run-up on the far wall rise and fall
/// back where Momentum's wall term, the under-resolved shear of the jet, pumped it out of the tank.
enum class WallAcceleration { Momentum, BodyForce };
/// The first-derivative rows at free-surface particles, whose supports the air cuts, when the
/// flow's gradient is a least-squares fit above linear order (FPM or KGF, gradient_order 2 or 3:
/// the `auto` gradient beside VRSPH): Linear, that method's linear fit (gradient_order=1) at the
/// surface particles without a wall particle among their neighbours (a wall's layers fill that
/// side of a support), the higher order elsewhere; Same, the higher order there too (as before
/// 2026-12-06). The one-sided quadratic fit at the surface row grew a dt-independent inviscid
/// instability in a tank at rest (nx = 10: spurious speed e^{0.8 t}, 1.9e-2 by t = 20); the
/// linear fit there holds it (docs/free_surface.md). Other gradients (a method's own) are left
/// as they are.
enum class SurfaceGradient { Linear, Same };
/// "eulerian" | "lagrangian"; "rk2" | "rk3"; "explicit" | "implicit". ConfigError otherwise.
FlowFrame parse_flow_frame(const std::string& name);
FlowScheme parse_flow_scheme(const std::string& name);
FlowViscosity parse_flow_viscosity(const std::string& name);
/// "momentum" | "body-force"; ConfigError otherwise.
WallAcceleration parse_wall_acceleration(const std::string& name);
/// "linear" | "same"; ConfigError otherwise.
SurfaceGradient parse_surface_gradient(const std::string& name);
std::string to_string(FlowFrame f);
std::string to_string(FlowScheme s);
std::string to_string(FlowViscosity v);
std::string to_string(WallAcceleration a);
std::string to_string(SurfaceGradient g);

/// Free surfaces: the largest condition number of a least-squares row (FPM's, the flow's
/// gradient) that is used; rows beyond it are left zero (FlowSolver).
constexpr Real free_surface_max_condition = 1e6;

/// SolverOptions with the iteration cap of the pressure solves (1000).
/// The largest pressure equation `auto` solves directly in the Lagrangian frame (in a build
/// with PETSc; else SolverOptions' own limit): 1000 particles in 2D, 500 in 3D.
constexpr Index lagrangian_direct_limit(int dim) { return dim == 3 ? 500 : 1000; }

inline SolverOptions pressure_solver_defaults() {
  SolverOptions o;
  o.max_iterations = 1000;
  // One V-cycle a preconditioner application: a stage that reuses an earlier stage's hierarchy
  // (FlowOptions::reuse_hierarchy) has a weaker preconditioner, which two cycles compound (the
  // Lagrangian vortex at nx = 32: 495 iterations over six steps against 443 with a new hierarchy
  // every stage, both with two cycles).
  o.two_cycles = false;
  return o;
}

struct FlowOptions {
  FlowFrame frame = FlowFrame::Eulerian;
  FlowScheme scheme = FlowScheme::RK3;
  /// Explicit: the viscous term in the Runge–Kutta rate (its stability bound limits dt, as
  /// ~dx²/ν); Implicit: ARS IMEX stages (one solve of (I - a dt ν L) per stage and component;
  /// implicit_viscosity.hpp says how), dt limited by the explicit terms only.
  FlowViscosity viscosity = FlowViscosity::Explicit;
  Real nu = 0.01;               ///< kinematic viscosity, >= 0
  Vec3 body_force = Vec3::Zero();  ///< g (components beyond the dimension must be 0)
  /// The velocity of each wall particle (tag Dirichlet), given its index and position; empty:
  /// walls at rest. It must not change in time, and walls may only slide along themselves
  /// (u·n = 0, checked).
  std::function<Vec3(Index, const Vec3&)> wall_velocity;
  /// The method, kernel and support of the operators (Laplacian and gradient are kept; the
  /// marked rows' method is the flow's own choice, surface_gradient).
  OperatorsOptions operators;
  /// The first derivatives (the projection's G and D, the advection): "auto" (VRSPH: FPM's
  /// second-order least-squares gradient, with VRSPH's Laplacian taking prefer=near unless its
  /// options say otherwise; any other method: its own), "own" (the method's), or a method name
  /// (operators.gradient_method_options its options). Why: docs/flow.md, "Which gradient".
  std::string gradient = "auto";
  /// The pressure Poisson solves. An iterative solve stops after 1000 iterations (a pressure
  /// matrix AMG cannot handle — FPM's Laplacian at 6.5e4 particles ran GMRES for minutes —
  /// fails with the solver's message instead; VRSPH's need 10–25).
  SolverOptions solver = pressure_solver_defaults();
  /// Lagrangian, direct solvers: one stage's factorisation preconditions BiCGSTAB on the next
  /// stages' pressure matrices (PressurePoisson::nearby) until it needs more than 30
  /// iterations; then the matrix of the moment is factorised. Off by default: measured on the
  /// Taylor-Green vortex (docs/flow.md) it is 16 % slower in 2D up to 1.7e4 particles, 2x
  /// faster at 6.6e4 and 3.2x faster in 3D at 3375, but GMRES + BoomerAMG, auto's choice there
  /// with PETSc, is faster still; it pays with a direct solver in 3D (a build without PETSc).
  bool reuse_factorisation = false;
  /// Lagrangian, PETSc (auto's choice above its direct limit): the AMG hierarchy of one stage's
  /// pressure matrix preconditions the next stages' (PressurePoisson::nearby, the same FGMRES
  /// and tolerance) while their solves take at most PressurePoisson::hierarchy_growth times the
  /// iterations of the hierarchy's own; then a new one is set up. The result is the same to the
  /// solver's tolerance. Lagrangian Taylor-Green at 1e5 and 1e6 particles: 0.67-0.68 of the
  /// PPE's seconds per step, with as many iterations (docs/flow.md).
  bool reuse_hierarchy = true;
  /// Defect corrections of every stage's pressure: after L p = D a (a the stage's forces minus
  /// advection), each correction solves L δ = D(a - G p) (the divergence of the rate the stage
  /// uses, walls held at rest) and adds δ, so that the rate is divergence-free to O(dx²) of the
  /// last defect instead of the O(dx²) of L - D G. Without them the divergence a stage leaves is
  /// removed by the end-of-step projection, a splitting whose error is O(dt dx²): results and
  /// steady states move with dt (docs/flow.md, "Defect corrections of the stage pressure").
  /// Each costs one more pressure solve per stage (a back substitution where the matrix is
  /// factorised). 0: none, as before 2026-12-06. Empty (the default): 1 with VRSPH's Laplacian,
  /// 0 with any other (with FPM's own Laplacian they raise the divergence they should remove and
  /// the pressure's error; SPH and MPS keep their published scheme). options() holds the value used.
  std::optional<int> pressure_corrections;
  bool allow_unstable = false;  ///< step() warns instead of refusing a time step beyond the limits
  /// Eulerian stabilisation: the term -c U dx³ L(L u) added to F (c this coefficient, U the
  /// velocity scale, dx the spacing), a hyperviscosity that damps the grid-scale modes a
  /// non-skew gradient excites on disordered particles while adding only an O(dx³) error
  /// (L u, L(L u) are O(1) and O(dx^-2)... see docs/flow.md). 0: none. Lagrangian: unused.
  Real hyperviscosity = 0;
  Real velocity_scale = 0;      ///< U of the hyperviscosity (0: the initial max |u|)
  /// Lagrangian: particle shifting after every step (shifting.hpp); Eulerian: must be none.
  ShiftingOptions shifting;
  /// Lagrangian: supports that follow the stretching of the particles instead of shifting them
  /// (docs/flow.md, "Regularity over time"). Before every step, while the smallest support
  /// isotropy of the fluid (analysis/support_isotropy.hpp) is below support_isotropy_target,
  /// every support radius grows by 15 %, up to support_growth times the base one; once it is
  /// above twice the target they shrink by 5 % a step toward the base. 1: off (the base radius).
  /// 0 (the default): growth up to kAutoLargestSupport spacings on a 2D periodic box without
  /// walls, free surface or shifting in the Lagrangian frame, where fixed supports lose the
  /// derivative across the flow's stretched columns and the run blows up (Taylor-Green nx = 64 at
  /// t = 0.24), capped below half the shortest period with the Verlet skin; 1 elsewhere.
  /// options() holds the value used.
  Real support_growth = 0;
  Real support_isotropy_target = 0.3;
  /// VRSPH's NNLS started from each row's previous active set at every update
  /// (OperatorsOptions::warm_start). Empty (the default): off where the supports grow by default
  /// (a 2D Lagrangian flow without walls, free surface or shifting), else operators.warm_start.
  /// Why off there: a warm row keeps its neighbours while they stay feasible, where a cold NNLS
  /// (with the flow's prefer=near) picks nearer ones, so over a thousand updates the Laplacian
  /// drifts to less accurate rows, and the Taylor-Green vortex's late error with it (docs/flow.md,
  /// "Cold volumes"). Costs up to about 30 % more time a step there (+29 % measured at 1.6e4
  /// particles, 6 dx supports). options() holds the value used.
  std::optional<bool> warm_start;
  /// A free surface: p = 0 at the fluid particles `surface` flags (its only_interior is always
  /// on, its spacing the flow's). Needs a body force or a moving initial state (ConfigError).
  bool free_surface = false;
  FreeSurfaceOptions surface;
  /// Lagrangian, walls: a fluid particle that ends a step closer than this many spacings to a
  /// face of the box holding wall particles is reflected off the plane at that distance (along
  /// the face's normal), its velocity interpolated there as a shift's (FlowStepReport::wall_pushes counts
  /// them); 0: never, and a particle that crosses a wall stops the run. A safety net for the
  /// lid's corners of a cavity (docs/flow.md); with extrapolated wall rows the water keeps off the
  /// walls by itself elsewhere.
  Real wall_gap = 0;
  /// The body force reaches g over this time, g (1 - cos(π t / T)) / 2 for t < T; 0: at once.
  Real body_force_ramp = 0;
  /// Free surfaces: what the walls' extrapolated pressure rows carry (WallAcceleration).
  WallAcceleration wall_acceleration = WallAcceleration::Momentum;
  /// Free surfaces: the gradient rows at the surface particles (SurfaceGradient).
  SurfaceGradient surface_gradient = SurfaceGradient::Linear;
  /// Without a body force, a step that leaves a particle faster than this many times the initial
  /// largest speed is an instability (NumericalError); 0: no such check. (The kinetic energy is
  /// checked too: it may not grow by 5 %.) With a body force g in a box closed along it: faster
  /// than this many times (the initial largest speed + 2 √(2 |g| D)), D the box's extent along g
  /// (twice a free fall across the box: the pressure's jets outrun free fall).
  Real max_speed_growth = 1.5;
};

/// One step's diagnostics.
struct FlowStepReport {
  Index step = 0;
  Real t = 0, dt = 0;
  Real kinetic_energy = 0;     ///< ½ Σ_i |u_i|² V (V: the box's measure over N)
  Real max_speed = 0;
  Real max_div_u = 0;          ///< max |D u| after the step
  Real cfl = 0;                ///< dt max|u| / dx
  Real advective_number = 0;   ///< dt × a bound of the advection operator's spectral radius (Eulerian)
  Real viscous_number = 0;     ///< dt × the explicit viscous (and hyperviscous) terms' spectral radius (Eulerian: measured; Lagrangian: Gershgorin bound)
  int ppe_iterations = 0;      ///< over the step's stages
  int ppe_setups = 0;          ///< pressure matrices set up afresh (the others solved on an earlier set-up: reuse_hierarchy)
  int viscous_iterations = 0;  ///< implicit viscosity: solver iterations over the step's stages and components
  Real ppe_shift = 0;          ///< largest |λ| of the step's projections (PressurePoisson)
  Real min_spacing = 0;        ///< smallest nearest-neighbour distance / dx
  Real max_spacing = 0;        ///< largest nearest-neighbour distance / dx (a hole grows it)
  /// Smallest support_isotropy (analysis/support_isotropy.hpp) over the fluid particles that are
  /// not on a free surface: 1 on a lattice, -> 0 as supports close onto lines (2D) or planes (3D).
  Real min_support_isotropy = 0;
  Real max_support_growth = 1; ///< largest support radius / the base one (FlowOptions::support_growth)
  Real max_shift = 0;          ///< largest shifting displacement of the step / dx
  Index wall_pushes = 0;       ///< particles FlowOptions::wall_gap reflected off a wall this step
  Real force_number = 0;       ///< free surface: dt / (0.25 (dx/|g|)^½), at most 1
  Index surface_particles = 0; ///< free surface: flagged particles after the step
  double seconds_update = 0, seconds_ppe = 0, seconds_rhs = 0;
  double seconds_viscous = 0;  ///< implicit viscosity: set-ups and solves
  std::vector<std::string> warnings;
};

/// The operators a flow with these options builds (FlowOptions::gradient resolved; with a free
/// surface and SurfaceGradient::Linear, marked_gradient_method the surface rows'): ConfigError
/// for an unknown gradient choice.
OperatorsOptions flow_operators(const FlowOptions& options);
/// The defect corrections a flow with these options takes (FlowOptions::pressure_corrections:
/// the value given, else 1 with VRSPH's Laplacian and 0 with the others).
int pressure_corrections_for(const FlowOptions& options);

/// FlowOptions::support_growth = 0 lets the supports grow up to this many spacings where it
/// applies: 3 times the default h = 3 dx, what was measured (docs/flow.md, "Supports that grow
/// when they close": order 1.35 / 1.47 at t = 1 with 6 / 9 spacings, the finest cloud never at
/// its cap with 9), whatever the user's h (a cap in units of h would reach 15 dx from h = 5 dx).
inline constexpr Real kAutoLargestSupport = 9;

namespace detail {
/// FlowOptions::support_growth's rule: the support radius of the next step from the current one,
/// the base and the largest radius, the smallest support isotropy of the fluid and the target.
Real next_support_radius(Real now, Real base, Real largest, Real least_isotropy, Real target);
}  // namespace detail

class FlowSolver {
 public:
  /// The cloud (a box: periodic axes, and wall particles tagged Dirichlet with normals along
  /// the others; fluid particles Interior) and the initial velocity (N x d; walls take
  /// wall_velocity), projected once so the run starts discretely divergence-free. ConfigError
  /// (a bounded box without walls, walls in the Lagrangian frame, bad options), InputError
  /// (shapes, non-finite values, walls without normals or moving through themselves).
  FlowSolver(PointCloud cloud, const Eigen::MatrixXd& u0, FlowOptions options);
  ~FlowSolver();
  FlowSolver(FlowSolver&&) noexcept;
  FlowSolver& operator=(FlowSolver&&) noexcept;

  /// One step of size dt. ConfigError for a dt beyond the limits (unless allow_unstable);
  /// NumericalError when the velocity stops being finite, its kinetic energy grows without a body
  /// force (by over 5 %: an instability) or a pressure solve fails; the search's and the methods'
  /// errors when particles pile up or lose their neighbours (GeometryError for coinciding or
  /// non-finite positions, which the search reports as InputError), and NumericalError when a particle
  /// leaves the box along a bounded axis (Lagrangian) — each naming the step.
  /// On a throw the state is that of the step before.
  const FlowStepReport& step(Real dt);
  /// The largest dt that meets the limits, times `safety` (in (0, 1]).
  Real stable_time_step(Real safety = 0.9) const;

  Real time() const { return t_; }
  Index steps() const { return steps_; }
  const Eigen::MatrixXd& velocity() const { return u_; }
  const std::vector<Vec3>& positions() const { return ops_->cloud().positions; }
  const Operators& operators() const { return *ops_; }
  const FlowOptions& options() const { return options_; }
  const FlowStepReport& last() const { return report_; }
  const Walls& walls() const { return eq_.walls; }
  /// The last free-surface detection (empty flags without a free surface).
  const FreeSurface& surface() const { return surface_; }
  /// The body force at time t (the ramp applied).
  Vec3 body_force(Real t) const;
  /// The pressure of the current velocity (zero mean): L p = D F_E(u), F_E the Eulerian
  /// right-hand side (the pressure that keeps ∂u/∂t divergence-free), one more solve.
  Field pressure() const;
  /// max |D u| of the current velocity over the fluid particles.
  Real max_divergence() const;

 private:
  struct Limits {
    Real advective = 0, viscous = 0;
  };
  Limits limits() const;
  Real advective_bound(const Eigen::MatrixXd& u) const;
  Real viscous_rate() const;
  Eigen::MatrixXd forces(const Eigen::MatrixXd& u, Real t) const;  ///< ν L u (- hyperviscosity) + g(t)
  /// The same from lap = L u (the vector Laplacian's rows; the walls' are replaced here).
  Eigen::MatrixXd forces(const Eigen::MatrixXd& u, Real t, Eigen::MatrixXd lap) const;
  Real force_limit() const;  ///< free surface: 0.25 (dx/|g|)^½, else infinity
  [[noreturn]] void explain_pressure_failure(const NumericalError& failure) const;
  void detect_surface();     ///< surface_ of the current positions
  std::vector<char> open_surface_rows() const;  ///< surface particles without a wall neighbour (SurfaceGradient)
  void wall_laplacian(const Eigen::MatrixXd& u, Eigen::MatrixXd& lap) const;  ///< at walls: Σ_a G_a G_a u
  /// The stage's pressure for the rate f - adv - G p (FlowOptions::pressure_corrections). IMEX:
  /// `implicit` is the stage's ν L u, which the first solve leaves to the end-of-step projection
  /// (imex_rates says why) and the corrections count in the rate whose divergence they remove
  /// (Stokes cavity, Re = 1: its kinetic energy at 15 times the explicit limit 1.7 % from a fine
  /// explicit run's with it, 8.5 % without; docs/flow.md).
  Field pressure_of(const Eigen::MatrixXd& f, const Eigen::MatrixXd& adv, Real t, FlowStepReport* r,
                    const Eigen::MatrixXd* implicit = nullptr) const;
  /// D(a - G p) at the fluid particles (walls at rest; 0 at walls and surface particles): the
  /// divergence a stage's rate keeps (FlowOptions::pressure_corrections).
  Field rate_divergence(const Eigen::MatrixXd& a, const Field& p) const;
  Eigen::MatrixXd rate(const Eigen::MatrixXd& u, Real t, FlowStepReport& r);
  /// The IMEX split of the rate: the explicit part (advection, pressure, body force,
  /// hyperviscosity) and ν L u at the fluid particles (zero at walls).
  std::pair<Eigen::MatrixXd, Eigen::MatrixXd> imex_rates(const Eigen::MatrixXd& u, Real t, FlowStepReport& r);
  /// Moves the particles (Lagrangian) to x^n + dt Σ a_j U_j for the given (a_j, U_j).
  using StageMove = std::function<void(const std::vector<std::pair<Real, const Eigen::MatrixXd*>>&)>;
  /// The velocity at the end of an IMEX step from un (Lagrangian: the particles moved as the
  /// explicit stages say).
  Eigen::MatrixXd imex_step(const Eigen::MatrixXd& un, Real dt, const StageMove& move, FlowStepReport& r);
  const ImexTableau& imex_tableau() const;  ///< ARS(4,4,3) for RK3, ARS(2,2,2) for RK2
  const ImplicitViscosity& viscous_solver(Real c, FlowStepReport& r);
  void move_to(const std::vector<Vec3>& x, FlowStepReport& r);
  /// The pressure equation of the current operators into ppe_ (and eq_'s wall fluxes); true when it
  /// is solved nearby the previous one (reuse_hierarchy, reuse_factorisation), false: set up afresh.
  bool factorise_pressure();
  /// Shifting and the wall gap: moves the particles by their displacements and interpolates u there.
  void shift(Eigen::MatrixXd& u, Real dt, FlowStepReport& r);
  /// The displacements that reflect the fluid particles at x off the planes wall_gap spacings off
  /// the wall faces (zero for the others).
  std::vector<Vec3> wall_gap_displacements(const std::vector<Vec3>& x) const;
  Eigen::MatrixXd project_state(const Eigen::MatrixXd& w, FlowStepReport& r);
  void finish_report(FlowStepReport& r) const;
  /// The smallest support_isotropy over the fluid particles off a free surface, and that particle
  /// (-1 when there is none).
  std::pair<Real, Index> least_isotropic_support() const;
  void adapt_supports();
  Real automatic_support_growth() const;  ///< FlowOptions::support_growth = 0 resolved
  /// A 2D Lagrangian flow without walls, free surface or shifting on this cloud: where the supports
  /// grow and the volumes start cold by default.
  bool stretches_freely(const PointCloud& cloud) const;
  Real kinetic_energy(const Eigen::MatrixXd& u) const;

  FlowOptions options_;
  std::unique_ptr<Operators> ops_;
  std::unique_ptr<PressurePoisson> ppe_;
  std::unique_ptr<ImplicitViscosity> viscous_;  ///< implicit viscosity: the current positions' and dt's
  PressureEquation eq_;  ///< its walls, wall fluxes and surface (the matrix is moved into ppe_)
  FreeSurface surface_;
  Eigen::MatrixXd u_;
  Field phi_;         ///< the last stage's pressure (the next solve's initial guess)
  Field correction_;  ///< the last end-of-step projection's potential (likewise)
  /// Per bounded axis, whether its low and high faces hold wall particles (the wall gap's faces).
  std::array<std::array<bool, 2>, 3> wall_faces_{};
  Real t_ = 0, spacing_ = 0, laplacian_bound_ = 0, gamma_ = 0;  ///< gamma_: the hyperviscosity c U dx³
  Index steps_ = 0;
  FlowStepReport report_;
  Real energy_bound_ = std::numeric_limits<Real>::infinity();  ///< no body force: 1.05 x the initial kinetic energy
  Real speed_bound_ = std::numeric_limits<Real>::infinity();   ///< no body force: max_speed_growth x the initial max |u|
};

}  // namespace vrsph
