// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Method: something that turns (cloud, neighbours, kernel) into stencils.
//
// Adding a method = a header/impl pair under methods/<family>/, one line in
// register_builtin_methods() (registry.cpp) and a section in docs/methods.md. The
// CLI listing, the conformance tests and the studies pick it up from the registry.
#include <memory>
#include <span>
#include <string>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

struct MethodInfo {
  std::string name;           ///< registry key, e.g. "sph"
  std::string source;         ///< where in the publications, by reference key: "[QW] §4-5" (references())
  std::string description;
  std::string claimed_order;  ///< what the paper claims, in words
  std::vector<OperatorKind> operators;
  /// Options the method reads: {key, "help (default ...)"}.
  std::vector<std::pair<std::string, std::string>> options;
  /// Named option sets (`profile=NAME`): {name, what it sets and why}; the first is the default.
  std::vector<std::pair<std::string, std::string>> profiles = {};
  /// Neighbour rings a second-derivative row reaches (2 for D2 = D D): studies size ghost
  /// layers by it.
  int stencil_rings = 1;
  /// div(a grad u) = a Δu + ∇a·∇u (no flux form, METHODS §3.0): the method reads
  /// StencilRequest::coefficient_gradient when given, so callers sample ∇a only for these.
  bool uses_coefficient_gradient = false;
  /// div(M grad u) with a diagonal tensor mobility M = diag(m_1..m_d) per particle
  /// (StencilRequest::mobility); methods without it refuse one with ConfigError.
  bool tensor_mobility = false;
  /// The scheme is designed to give non-negative off-diagonal weights (a two-point-flux,
  /// monotone matrix: SPH/Morris, VRSPH, Brookshaw, M-SPH); the BVP layer warns, naming the
  /// rows, when a stencil of such a method has negative ones all the same.
  bool monotone = false;
  bool supports(OperatorKind k) const;  ///< method.build makes it
  /// build_stencil makes it: supports(), or the Hessian (hessian_rows on the method's neighbours and kernel).
  bool provides(OperatorKind k) const { return k == OperatorKind::Hessian || supports(k); }
  /// Every operator it provides: `operators`, then the Hessian where build_stencil adds it (the listings).
  std::vector<OperatorKind> provided() const;
};

/// Everything a method may look at. Row i uses the support radius neighbours.radius(i)
/// (gather convention); `spacing` is the nominal dx (for volumes v = dx^d).
struct Discretisation {
  const PointCloud& cloud;
  const NeighbourList& neighbours;
  KernelType kernel = KernelType::CubicSpline;
  Real spacing = 0;
  /// Particles of the whole cloud when `cloud` is one rank's part with its halo (0: cloud.size()):
  /// what |Omega|/N-type volumes divide by.
  Index total_particles = 0;
  /// The whole cloud's length unit (length_scale) when `cloud` is one rank's part (0: that of
  /// `cloud`), so that every rank writes its local systems in the serial run's unit.
  Real length = 0;
  Kernel kernel_at(Index i) const { return Kernel(kernel, cloud.dim, neighbours.radius(i)); }
  /// Where row i sees its k-th neighbour: x_j, or its periodic image when the list crosses
  /// periodic faces (NeighbourList::shifts; only methods that read_periodic_pairs take such lists).
  Vec3 neighbour_position(Index i, Index k) const {
    const auto e = static_cast<std::size_t>(neighbours.offsets[static_cast<std::size_t>(i)] + k);
    const Vec3& xj = cloud.positions[static_cast<std::size_t>(neighbours.indices[e])];
    return neighbours.shifts.empty() ? xj : Vec3(xj + periodic_shift(cloud.domain, neighbours.shifts[e]));
  }
  Real length_unit() const { return length > 0 ? length : length_scale(cloud); }
};

/// What the rows are for. Values: row i approximates the operator at x_i, so apply(stencil, u)
/// is compared with (L u)(x_i) (operator studies, spectra, time steppers, Python stencil()).
/// System: the rows are equations of a boundary value problem; a method may then give rows
/// whose right-hand side is a weighted average of f (Stencil::rhs, VRSPH rhs=compact) and
/// Neumann rows that take the flux data themselves (Stencil::wall_flux, VRSPH flux=balance).
/// A method's option left at "auto" chooses by this (docs/methods.md, "Defaults and profiles").
enum class StencilUse { Values, System };

struct StencilRequest {
  OperatorKind kind = OperatorKind::Laplacian;
  /// Values of a(x) > 0 at every particle; required for DivAGrad.
  const Field* coefficient = nullptr;
  /// Optional exact grad a (N x dim); methods without a flux form (Taylor-corrected
  /// ones) use it in a Laplacian + grad(a).grad formulation, others ignore it.
  const Eigen::MatrixXd* coefficient_gradient = nullptr;
  /// Rows to compute (1) or leave empty (0); empty span = every non-ghost particle.
  /// A boundary value problem asks only for its unknowns' rows.
  std::span<const char> rows = {};
  /// DivAGrad with a diagonal tensor mobility: N x dim values m_k(x_i) > 0, in place of
  /// `coefficient` (exactly one of the two is given); only MethodInfo::tensor_mobility methods.
  const Eigen::MatrixXd* mobility = nullptr;
  /// Point values or the equations of a boundary value problem (last, so that positional
  /// initialisers {kind, coefficient, ...} keep their meaning).
  StencilUse use = StencilUse::Values;
};

/// What a method keeps from one build of a request to the next on particles that have moved
/// (Method::rebuild): VRSPH's NNLS active sets and volume arrays. Opaque to callers.
class BuildState {
 public:
  virtual ~BuildState() = default;
};

class Method {
 public:
  virtual ~Method() = default;
  virtual const MethodInfo& info() const = 0;
  /// Rows of ghost particles are left empty (zero). Throws ConfigError for an
  /// unsupported operator, InputError for bad coefficients.
  virtual Stencil build(const Discretisation& disc, const StencilRequest& request) const = 0;
  /// The same stencil after the particles moved: `out` holds the previous build of this request
  /// (its storage is reused) and `state` what the method kept from it (null at the first call:
  /// the method creates its own; keep one state per request). The default builds afresh, equal
  /// to build(). With `warm_start`, VRSPH starts each row's NNLS from the neighbours it used at
  /// the previous build: the same moment conditions to the NNLS tolerance, possibly at another
  /// optimal vertex than a fresh build (docs/moving.md); without, its rebuild equals build().
  virtual void rebuild(const Discretisation& disc, const StencilRequest& request, Stencil& out,
                       std::unique_ptr<BuildState>& /*state*/, bool /*warm_start*/) const {
    out = build(disc, request);
  }
  /// True when this request's rows read their neighbours only through pair vectors and distances
  /// (Discretisation::neighbour_position), so that a minimum-image list with periodic shifts can be
  /// given directly (Operators on a periodic box: Verlet list and warm start). False: such a list
  /// is refused and periodic boxes go through periodic_stencil's images.
  virtual bool reads_periodic_pairs(const StencilRequest& /*request*/) const { return false; }
  /// Moving particles: lets the next rebuild of a first-derivative request (its state
  /// `borrower`, created if null) take the volumes that this method's rebuild of a Laplacian
  /// request (its state `lender`) has just found on the same neighbour list, in the rows where
  /// they also meet the first-derivative moment conditions; null: nothing lent. For one rebuild
  /// only, and only with a warm start (which already lets a rebuild take another optimum of
  /// the same NNLS: VRSPH's Laplace conditions contain the gradient's, so a Laplace solution
  /// is one). Default: nothing is shared.
  virtual void lend_volumes(std::unique_ptr<BuildState>& /*borrower*/, const BuildState* /*lender*/) const {}
  /// Rows of the last rebuild whose NNLS started warm, and those the guess solved as it stood
  /// (0, 0 for methods without a warm start).
  virtual std::pair<Index, Index> warm_start_counts(const BuildState* /*state*/) const { return {0, 0}; }
  /// Rows of the last rebuild that took lent volumes (lend_volumes) instead of solving their own.
  virtual Index borrowed_volume_rows(const BuildState* /*state*/) const { return 0; }
  /// How many supports away from a row's particle its weights read the cloud: 1 when row i
  /// uses only its own neighbours; 2 when it also uses quantities built from each neighbour's
  /// own neighbour list (D2 = D D, Shepard or Voronoi volumes of the neighbours); 3 for VRSPH
  /// volumes of the neighbours (averages of the NNLS volumes of every row that sees them). A
  /// distributed solve sizes its halo by it (reach x h).
  virtual int reach() const { return info().stencil_rings; }
  /// The same for the rows a request of this use gets, in supports (not always whole ones), where
  /// the method's options make it depend on the use (VRSPH's compact rows of a boundary value
  /// problem reach 1.25 supports: their wider support, compact_wide). Default: reach().
  virtual Real reach_for(StencilUse /*use*/) const { return reach(); }
  /// Supports away from a row at which its weights read ∇a when this method estimates it
  /// itself (needs_coefficient_gradient, none given): 1 when a row fits ∇a at its own
  /// particle (the Taylor-type methods), 2 when it reads ∇a at its neighbours, each fitted
  /// over that neighbour's support (VRSPH compact rows; 2.25 with their wider support). A
  /// distributed solve widens its halo.
  virtual Real estimated_gradient_reach() const { return 1; }
  /// True when this method's Laplacian / div(a grad) rows at Neumann particles are balance
  /// rows (Stencil::wall_flux) that take the flux data themselves, for requests of this use:
  /// a boundary value problem then asks for those rows in the operator request and builds no
  /// gradient (flux) stencil.
  virtual bool balances_flux_rows(StencilUse /*use*/) const { return false; }
  /// True when this method (with its options) wants StencilRequest::coefficient_gradient for
  /// div(a grad) rows of this use: the Taylor-type methods' a Δu + ∇a·∇u form, VRSPH compact rows.
  virtual bool needs_coefficient_gradient(StencilUse /*use*/) const { return info().uses_coefficient_gradient; }
  /// The row forms this method's options resolve to for `use`, in words, when an option left
  /// at its default chooses by the use (empty otherwise): what the CLI and Python print so that
  /// an operator-level run never silently differs from a boundary value problem.
  virtual std::string row_forms(StencilUse /*use*/) const { return {}; }
};

/// Supports away from a row that its weights read for this use: Method::reach, or further
/// when the method fits ∇a itself (no coefficient gradient given): estimated_gradient_reach.
/// A halo (a rank's, or the periodic images) must be this many supports wide.
Real rows_reach(const Method& method, StencilUse use, bool coefficient_gradient_given);

/// Shared checks for every method: operator supported, sizes agree, a > 0 and finite, and no
/// periodic shifts in the list unless `periodic_pairs` (the method reads them).
void check_request(const MethodInfo& info, const Discretisation& disc, const StencilRequest& request,
                   bool periodic_pairs = false);
/// div(a grad)'s scalar coefficient: one value per particle, each positive and finite
/// (InputError naming the count or the particle).
void check_scalar_coefficient(const PointCloud& cloud, const Field& a);

/// Whether row i is to be built: the requested rows, or every non-ghost particle.
inline bool row_requested(const PointCloud& cloud, const StencilRequest& req, Index i) {
  const auto si = static_cast<std::size_t>(i);
  return req.rows.empty() ? cloud.tags[si] != Tag::Ghost : req.rows[si] != 0;
}

/// Stores a pair's gradient weight g in stencil slot `slot`: all components for
/// OperatorKind::Gradient, the requested one for Dx/Dy/Dz.
inline void store_pair_gradient(Stencil& s, OperatorKind kind, int dim, std::size_t slot, const Vec3& g) {
  if (kind == OperatorKind::Gradient)
    for (int c = 0; c < dim; ++c) s.values[static_cast<std::size_t>(c)][slot] = g[c];
  else
    s.values[0][slot] = g[kind == OperatorKind::Dy ? 1 : kind == OperatorKind::Dz ? 2 : 0];
}

}  // namespace vrsph
