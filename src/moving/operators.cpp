// SPDX-License-Identifier: BSD-3-Clause
// Operators on moving particles (operators.hpp).
#include <algorithm>
#include <cmath>
#include <utility>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/moving/operators.hpp>
#include <vrsph/stencil/algebra.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

Operators::Operators(PointCloud cloud, OperatorsOptions options) : cloud_(std::move(cloud)), options_(std::move(options)) {
  validate(cloud_);
  method_ = builtin_methods().create(options_.method, options_.method_options);
  if (!options_.gradient_method.empty())
    gradient_method_ = builtin_methods().create(options_.gradient_method, options_.gradient_method_options);
  if (!options_.marked_gradient_method.empty()) {
    marked_method_ = builtin_methods().create(options_.marked_gradient_method, options_.marked_gradient_method_options);
    check<ConfigError>(marked_method_->info().provides(OperatorKind::Gradient), "operators: the marked rows' method ",
                       options_.marked_gradient_method, " has no gradient operator");
  }
  check<ConfigError>(!options_.operators.empty(), "operators: no operator asked for");
  for (const OperatorKind k : options_.operators) {
    check<ConfigError>(method_of(k).info().provides(k), "operators: method ", method_of(k).info().name, " has no ",
                       to_string(k), " operator");
    const bool repeated = std::count(options_.operators.begin(), options_.operators.end(), k) > 1;
    check<ConfigError>(!repeated, "operators: ", to_string(k), " asked for twice");
    kept_.emplace_back().kind = k;
  }
  const bool div_a_grad = keeps(OperatorKind::DivAGrad);
  check<ConfigError>(div_a_grad || options_.coefficient.size() == 0, "operators: a coefficient was given but div-a-grad is "
                     "not among the operators (the coefficient serves only div(a grad))");
  if (div_a_grad) {
    check<ConfigError>(options_.coefficient.size() > 0, "operators: div-a-grad needs the coefficient a at every particle "
                       "(OperatorsOptions::coefficient; Python: coefficient=)");
    check_scalar_coefficient(cloud_, options_.coefficient);
    coefficient_ = options_.coefficient;
  }
  check<ConfigError>(std::isfinite(options_.skin) && options_.skin >= 0, "operators: the Verlet skin (a fraction of the "
                     "support radius) must be finite and >= 0, got ", options_.skin);
  // A wider skin only makes each search larger (candidates ~ (1 + skin)^d times the list).
  check<ConfigError>(options_.skin <= 2, "operators: a Verlet skin of ", options_.skin, " support radii searches (1 + skin)^d = ",
                     std::pow(1 + options_.skin, cloud_.dim), " times the pairs the list keeps; give at most 2 (0.2-0.3 is "
                     "usual)");
  check<ConfigError>(options_.min_neighbours >= 0, "operators: the least neighbour count must be >= 0, got ",
                     options_.min_neighbours);
  spacing_ = estimate_spacing(cloud_);  // as vrsph.stencil and the CLI
  if (options_.radius > 0) {
    check<ConfigError>(std::isfinite(options_.radius), "operators: the support radius must be finite");
    radius_ = options_.radius;
  } else {
    check<ConfigError>(std::isfinite(options_.h_factor) && options_.h_factor > 0, "operators: h_factor must be positive, got ",
                       options_.h_factor);
    radius_ = options_.h_factor * spacing_;
  }
  check_support_is_local(radius_, cloud_extent(cloud_), options_.radius > 0 ? 0 : options_.h_factor);
  verlet_ = std::make_unique<VerletNeighbours>(search_params(), options_.skin * radius_);
  update_stencils(update_neighbours());
}

Operators::~Operators() = default;
Operators::Operators(Operators&&) noexcept = default;
Operators& Operators::operator=(Operators&&) noexcept = default;

void Operators::update(std::span<const Vec3> positions) { update(positions, UpdateWith{}); }

void Operators::update(std::span<const Vec3> positions, const Field& coefficient) {
  update(positions, UpdateWith{&coefficient, nullptr});
}

void Operators::update(std::span<const Vec3> positions, const UpdateWith& with) {
  check<InputError>(static_cast<Index>(positions.size()) == cloud_.size(), "operators update: ", positions.size(),
                    " positions for ", cloud_.size(), " particles (particles cannot be added or removed: build new "
                    "Operators)");
  if (with.coefficient) {
    check<ConfigError>(keeps(OperatorKind::DivAGrad), "operators update: a coefficient was given but div-a-grad is not kept");
    check_scalar_coefficient(cloud_, *with.coefficient);  // before anything changes (a method checks half-way)
  }
  // The old positions are kept (swapped: no allocation after the first step) so that a failed
  // update leaves the operators as they were: the neighbour phase changes nothing when it
  // throws; a stencil phase that throws half-way is redone on the old positions (the old
  // coefficient, the old list).
  previous_.swap(cloud_.positions);
  cloud_.positions.assign(positions.begin(), positions.end());
  const NeighbourList* nl = nullptr;
  NeighbourList given;
  try {
    if (with.candidates) {
      validate(cloud_);
      const Stopwatch watch;
      UserNeighbours u = *with.candidates;
      u.radii = verlet_->radii();
      u.candidates = true;
      u.min_neighbours = options_.min_neighbours;
      given = neighbour_list_from(cloud_, u);
      stats_.searched = false;
      stats_.seconds_neighbours = watch.seconds();
      nl = &given;
    } else {
      nl = &update_neighbours();
    }
  } catch (...) {
    cloud_.positions.swap(previous_);
    throw;
  }
  Field old_coefficient;
  if (with.coefficient) {
    old_coefficient = std::move(coefficient_);
    coefficient_ = *with.coefficient;
  }
  const bool was_given = given_current_;
  if (with.candidates) {  // the list the stencils will hold on to (the previous kept until they are built)
    std::swap(given, given_);
    nl = &given_;
  }
  given_current_ = with.candidates != nullptr;
  try {
    update_stencils(*nl);
  } catch (...) {
    cloud_.positions.swap(previous_);
    if (with.coefficient) coefficient_ = std::move(old_coefficient);
    given_current_ = was_given;
    if (with.candidates) std::swap(given, given_);
    update_stencils(was_given ? given_ : update_neighbours());
    throw;
  }
  ++stats_.updates;
}

const NeighbourList& Operators::current_list() const { return given_current_ ? given_ : verlet_->list(); }

void Operators::set_coefficient(Field coefficient) {
  check<ConfigError>(keeps(OperatorKind::DivAGrad), "operators: set_coefficient, but div-a-grad is not among the operators");
  check_scalar_coefficient(cloud_, coefficient);
  coefficient_.swap(coefficient);
  try {
    update_stencils(current_list(), OperatorKind::DivAGrad);
  } catch (...) {
    coefficient_.swap(coefficient);
    update_stencils(current_list(), OperatorKind::DivAGrad);
    throw;
  }
}

bool Operators::keeps(OperatorKind kind) const {
  return std::find(options_.operators.begin(), options_.operators.end(), kind) != options_.operators.end();
}

void Operators::set_support_radii(std::vector<Real> radii) {
  verlet_->set_radii(std::move(radii));
  own_radii_ = true;
}

const std::vector<Real>& Operators::support_radii() const { return verlet_->radii(); }

SearchParams Operators::search_params() const {
  SearchParams sp;
  sp.radius = radius_;
  if (own_radii_) sp.radii = verlet_->radii();
  sp.backend = options_.backend;
  sp.min_neighbours = options_.min_neighbours;
  return sp;
}

const NeighbourList& Operators::update_neighbours() {
  validate(cloud_);
  const Stopwatch watch;
  const NeighbourList& nl = verlet_->update(cloud_);  // on a periodic box: minimum images, with shifts
  stats_.searches = verlet_->searches();
  stats_.searched = verlet_->last_searched();
  stats_.seconds_neighbours = watch.seconds();
  return nl;
}

namespace {

bool first_derivative(OperatorKind kind) {
  return kind == OperatorKind::Gradient || kind == OperatorKind::Dx || kind == OperatorKind::Dy || kind == OperatorKind::Dz;
}

}  // namespace

void Operators::update_stencils(const NeighbourList& nl, std::optional<OperatorKind> only) {
  const Stopwatch watch;
  stats_.warm_rows = stats_.warm_hits = stats_.borrowed_rows = 0;
  const Discretisation disc{cloud_, nl, options_.kernel, spacing_};
  // The Laplacian first: with a warm start its volumes, found on this very list, may serve the
  // first-derivative rows of the same method (Method::lend_volumes: VRSPH's gradient rows skip
  // their own NNLS where the Laplace volumes meet their conditions; 0.86 x the stencils' time at
  // 10^6 moving 2D particles). The construction's first build borrows too.
  const BuildState* lender = nullptr;
  const Method* lender_method = nullptr;
  for (const bool laplacian_pass : {true, false})
    for (Kept& k : kept_) {
      if ((k.kind == OperatorKind::Laplacian) != laplacian_pass) continue;
      if (only && k.kind != *only) {
        // Not rebuilt (set_coefficient): the Laplacian's volumes, still those of this list, lend.
        if (k.kind == OperatorKind::Laplacian && k.rebuilt) {
          lender = k.state.get();
          lender_method = &method_of(k.kind);
        }
        continue;
      }
      StencilRequest req;
      req.kind = k.kind;
      req.use = options_.use;
      if (k.kind == OperatorKind::DivAGrad) req.coefficient = &coefficient_;
      const Method& method = method_of(k.kind);
      if (k.kind == OperatorKind::Hessian) {  // rows read only pair vectors: the minimum-image list serves
        k.stencil = hessian_rows(disc, req, method.info().name);
        continue;
      }
      // (And div(a grad)'s rows, whose NNLS is the Laplacian's own problem: they take all its volumes.)
      if ((first_derivative(k.kind) || k.kind == OperatorKind::DivAGrad) && options_.warm_start && options_.share_volumes &&
          lender_method == &method)
        method.lend_volumes(k.state, lender);
      const bool rebuilt = build_rows(method, disc, req, k.stencil, k.state);
      k.rebuilt = rebuilt;
      if (!rebuilt && k.state) method.lend_volumes(k.state, nullptr);  // built on images: nothing left lent
      if (k.kind == OperatorKind::Laplacian && rebuilt) {
        lender = k.state.get();
        lender_method = &method;
      }
      splice_marked(k, disc);
    }
  stats_.seconds_stencils = watch.seconds();
}

bool Operators::build_rows(const Method& method, const Discretisation& disc, StencilRequest req, Stencil& out,
                           std::unique_ptr<BuildState>& state) {
  // A periodic box whose rows need more than pair vectors: built afresh on the periodic images,
  // columns folded back. Otherwise (VRSPH's point rows) the minimum-image list serves directly.
  if (!disc.neighbours.shifts.empty() && !method.reads_periodic_pairs(req)) {
    out = periodic_stencil(method, cloud_, search_params(), options_.kernel, spacing_, req);
    return false;
  }
  method.rebuild(disc, req, out, state, options_.warm_start);
  const auto [rows, hits] = method.warm_start_counts(state.get());
  stats_.warm_rows += rows;
  stats_.warm_hits += hits;
  stats_.borrowed_rows += method.borrowed_volume_rows(state.get());
  return true;
}

void Operators::splice_marked(Kept& k, const Discretisation& disc) {
  k.use_spliced = marked_method_ && first_derivative(k.kind) &&
                  std::any_of(marked_.begin(), marked_.end(), [](char c) { return c != 0; });
  if (!k.use_spliced) return;
  StencilRequest req;
  req.kind = k.kind;
  req.use = options_.use;
  req.rows = marked_;
  build_rows(*marked_method_, disc, req, k.marked, k.marked_state);
  splice_rows(k.stencil, k.marked, marked_, k.spliced);
}

void Operators::set_marked_rows(std::vector<char> marked) {
  check<InputError>(marked.empty() || static_cast<Index>(marked.size()) == cloud_.size(), "operators: ", marked.size(),
                    " marked-row flags for ", cloud_.size(), " particles (one per particle, or none)");
  const bool any = std::any_of(marked.begin(), marked.end(), [](char c) { return c != 0; });
  check<ConfigError>(!any || marked_method_, "operators: rows were marked but no marked_gradient_method builds them");
  std::vector<char> before = std::move(marked_);
  marked_ = std::move(marked);
  const Discretisation disc{cloud_, current_list(), options_.kernel, spacing_};
  try {
    for (Kept& k : kept_) splice_marked(k, disc);
  } catch (...) {
    marked_ = std::move(before);
    for (Kept& k : kept_) splice_marked(k, disc);
    throw;
  }
}

const Method& Operators::method_of(OperatorKind kind) const {
  return first_derivative(kind) && gradient_method_ ? *gradient_method_ : *method_;
}

const NeighbourList& Operators::neighbours() const { return current_list(); }

const Stencil& Operators::stencil(OperatorKind kind) const {
  for (const Kept& k : kept_)
    if (k.kind == kind) return k.use_spliced ? k.spliced : k.stencil;
  throw ConfigError(detail::concat("operators: no ", to_string(kind), " stencil kept (ask for it in the operators)"));
}

Eigen::MatrixXd Operators::apply(OperatorKind kind, const Field& u) const { return vrsph::apply(stencil(kind), u); }

Eigen::MatrixXd Operators::apply(VectorOperator op, const Eigen::MatrixXd& U) const {
  return apply_vector(op, stencil(base_operator(op)), U);
}

}  // namespace vrsph
