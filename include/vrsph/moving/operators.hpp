// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Operators: one method's stencils on a cloud whose particles move, built once and then
// update()d every time step at a fraction of the cost of a fresh build:
//  - the neighbour list is kept with a Verlet skin (neighbours/verlet.hpp): a search only
//    when particles have moved far enough, otherwise the stored candidates re-filtered;
//  - every stencil is rebuilt into its previous storage (Method::rebuild), and VRSPH starts
//    each row's NNLS from the neighbours that row used at the previous step (warm start);
//  - vector operators (divergence, curl, vector Laplacian) come from the gradient and
//    Laplacian stencils (stencil/vector_operators.hpp).
// On a periodic box the list holds minimum images (periodic shifts): VRSPH's point rows read it
// directly, with the skin and the warm start; other methods' rows are built afresh on the
// periodic images at each update (periodic_stencil; docs/moving.md).
#include <memory>
#include <optional>
#include <span>
#include <vrsph/methods/method.hpp>
#include <vrsph/neighbours/user_list.hpp>
#include <vrsph/neighbours/verlet.hpp>
#include <vrsph/stencil/vector_operators.hpp>

namespace vrsph {

struct OperatorsOptions {
  std::string method = "vrsph";
  MethodOptions method_options;
  /// The method of the first-derivative stencils (gradient, dx/dy/dz) when it is another one
  /// (empty: `method`): a flow's projection pairs VRSPH's Laplacian with a least-squares
  /// gradient (docs/flow.md). Both share the one neighbour list.
  std::string gradient_method;
  MethodOptions gradient_method_options;
  /// The method of the first-derivative rows at the particles the caller marks (set_marked_rows;
  /// empty: no rows are marked): rows whose supports are cut, e.g. a free surface's, where a
  /// flow's quadratic least-squares gradient is one-sided and a linear fit is stable
  /// (docs/free_surface.md). The marked rows are rebuilt with it at every update.
  std::string marked_gradient_method;
  MethodOptions marked_gradient_method_options;
  KernelType kernel = KernelType::CubicSpline;
  Real h_factor = 3;  ///< support radius = h_factor x spacing (estimate_spacing: the cloud's, else from its nearest distances)
  Real radius = 0;    ///< > 0: this support radius instead
  /// The stencils kept: Laplacian, DivAGrad, Gradient, Dx/Dy/Dz, Hessian (the Hessian rows are
  /// hessian_rows', rebuilt at every update: they keep nothing from one to the next).
  std::vector<OperatorKind> operators = {OperatorKind::Laplacian, OperatorKind::Gradient};
  /// DivAGrad's scalar coefficient a > 0, one value per particle, carried by its particle (a
  /// material property: ISPH's 1/rho of two fluids, a conductivity); set_coefficient() or
  /// update(positions, coefficient) replace it. Required with DivAGrad, refused without it.
  Field coefficient;
  StencilUse use = StencilUse::Values;
  Real skin = 0.2;         ///< Verlet skin as a fraction of the support radius (0: search every update)
  bool warm_start = true;  ///< VRSPH: start each row's NNLS from its previous active set
  /// With warm_start, VRSPH: the gradient (dx/dy/dz) rows take the Laplacian's volumes where these
  /// meet the Laplace conditions (which contain the gradient's) instead of solving their own NNLS
  /// (UpdateStats::borrowed_rows; docs/moving.md). False: every stencil solves its own.
  bool share_volumes = true;
  SearchBackend backend = SearchBackend::CellList;
  /// Rows with fewer neighbours than this raise GeometryError (SearchParams::min_neighbours).
  /// 0 lets a particle stand alone with empty rows: a free-surface flow's droplet, whose
  /// pressure is the air's and which falls freely (flow_solver.hpp).
  Index min_neighbours = 1;
};

/// What an update may change besides the positions (Operators::update).
struct UpdateWith {
  /// DivAGrad's new coefficient, one value per particle (null: a stays with its particles).
  const Field* coefficient = nullptr;
  /// The caller's candidate pairs at the new positions (its own cell or Verlet list: offsets,
  /// indices, optionally distances; any superset of the pairs within the support radii), used
  /// instead of the operators' Verlet list for this update (null: the Verlet list). Filtered
  /// to the radii and checked by neighbour_list_from (user_list.hpp; its `radii` and
  /// `candidates` are the operators' own); the Verlet list stays valid for later updates.
  const UserNeighbours* candidates = nullptr;
};

/// What the last update did and cost.
struct UpdateStats {
  Index updates = 0;            ///< update() calls so far (the construction not counted)
  Index searches = 0;           ///< neighbour searches so far (the construction's included)
  bool searched = false;        ///< whether the last build searched
  Index warm_rows = 0;          ///< rows of the last build whose NNLS started warm (all stencils)
  Index warm_hits = 0;          ///< of those, rows whose guess was optimal as it stood
  /// First-derivative rows of the last build that took the Laplacian's volumes (VRSPH with a warm
  /// start: its Laplace conditions contain the gradient's) instead of solving their own NNLS.
  Index borrowed_rows = 0;
  double seconds_neighbours = 0;  ///< the last build's neighbour list
  double seconds_stencils = 0;    ///< the last build's stencils
};

class Operators {
 public:
  /// Builds the stencils on the cloud as given. ConfigError for an operator that the method
  /// lacks, DivAGrad without a coefficient (or a coefficient without DivAGrad), bad options;
  /// InputError for a bad coefficient, InputError/GeometryError as a search and the method raise them.
  Operators(PointCloud cloud, OperatorsOptions options);
  ~Operators();
  Operators(Operators&&) noexcept;
  Operators& operator=(Operators&&) noexcept;

  /// The particles moved to `positions` (same count; components beyond the dimension 0):
  /// the neighbour list and every stencil rebuilt. InputError for another count, non-finite
  /// or out-of-dimension coordinates, a particle outside a periodic box; the previous state
  /// is kept when it throws.
  void update(std::span<const Vec3> positions);
  /// The same with a new coefficient of div(a grad) (DivAGrad kept; one positive finite value per
  /// particle): both replaced together, or neither when it throws.
  void update(std::span<const Vec3> positions, const Field& coefficient);
  /// The same with what `with` gives (a coefficient, the caller's candidate pairs); InputError for
  /// a candidate list neighbour_list_from refuses (naming the row), nothing changed.
  void update(std::span<const Vec3> positions, const UpdateWith& with);

  /// DivAGrad's coefficient from now on: its stencil is rebuilt on the current positions.
  /// ConfigError when DivAGrad is not kept, InputError for another count or a value that is not
  /// positive and finite (naming the particle); nothing changed when it throws.
  void set_coefficient(Field coefficient);
  const Field& coefficient() const { return coefficient_; }

  /// Per-particle support radii from the next update() on, one per particle (each positive,
  /// finite and, on a periodic box, below half the shortest period less the skin): e.g. supports
  /// grown where the particles lost their isotropy (FlowOptions::support_growth). The rows of
  /// every method read their own particle's radius. InputError otherwise, nothing changed.
  /// radius() stays the base radius.
  void set_support_radii(std::vector<Real> radii);
  /// The support radius of each particle's row (all radius() unless set_support_radii).
  const std::vector<Real>& support_radii() const;

  /// Marks particles (one flag per particle; empty: none) whose first-derivative rows (gradient,
  /// dx/dy/dz) marked_gradient_method builds, from now on and at every update until marked
  /// again: their rows are rebuilt now. ConfigError without a marked_gradient_method (unless
  /// the flags are all 0), InputError for another count; nothing changed when it throws.
  void set_marked_rows(std::vector<char> marked);
  const std::vector<char>& marked_rows() const { return marked_; }

  const PointCloud& cloud() const { return cloud_; }
  Real radius() const { return radius_; }
  Real spacing() const { return spacing_; }
  const NeighbourList& neighbours() const;
  /// ConfigError if `kind` is not kept.
  const Stencil& stencil(OperatorKind kind) const;
  /// The operator applied to a scalar field (N values): N x components.
  Eigen::MatrixXd apply(OperatorKind kind, const Field& u) const;
  /// Divergence, curl or vector Laplacian of U (N x dim), from the gradient / Laplacian stencil.
  Eigen::MatrixXd apply(VectorOperator op, const Eigen::MatrixXd& U) const;
  const UpdateStats& stats() const { return stats_; }
  const OperatorsOptions& options() const { return options_; }

 private:
  SearchParams search_params() const;
  bool keeps(OperatorKind kind) const;
  const NeighbourList& current_list() const;
  const NeighbourList& update_neighbours();
  /// Every kept stencil, or only `only`'s (the others as they are).
  void update_stencils(const NeighbourList& neighbours, std::optional<OperatorKind> only = std::nullopt);

  struct Kept {
    OperatorKind kind;
    Stencil stencil;  ///< the method's rows everywhere
    std::unique_ptr<BuildState> state;
    Stencil marked;   ///< marked_gradient_method's rows at the marked particles (others empty)
    std::unique_ptr<BuildState> marked_state;
    Stencil spliced;  ///< stencil with the marked rows from `marked`: what stencil() gives when rows are marked
    bool use_spliced = false;
    bool rebuilt = false;  ///< the last build was the method's rebuild (its state describes it), not on images
  };
  /// False when the rows were built afresh on periodic images (the method's state untouched).
  bool build_rows(const Method& method, const Discretisation& disc, StencilRequest req, Stencil& out,
                  std::unique_ptr<BuildState>& state);
  void splice_marked(Kept& k, const Discretisation& disc);
  PointCloud cloud_;
  OperatorsOptions options_;
  const Method& method_of(OperatorKind kind) const;
  std::unique_ptr<Method> method_;
  std::unique_ptr<Method> gradient_method_;  ///< null: method_ builds the first derivatives too
  std::unique_ptr<Method> marked_method_;    ///< null: no marked rows
  std::vector<char> marked_;                 ///< set_marked_rows's flags (empty or all 0: none)
  Field coefficient_;                        ///< DivAGrad's a at the particles (empty without DivAGrad)
  Real spacing_ = 0, radius_ = 0;
  std::unique_ptr<VerletNeighbours> verlet_;
  std::vector<Vec3> previous_;   ///< the positions before the update under way
  bool own_radii_ = false;       ///< set_support_radii was called: searches take the per-particle radii
  std::vector<Kept> kept_;
  NeighbourList given_;        ///< the last update's list from the caller's candidates
  bool given_current_ = false; ///< the stencils were built on given_ (else on the Verlet list)
  UpdateStats stats_;
};

}  // namespace vrsph
