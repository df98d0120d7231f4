// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <array>
#include <vrsph/core/error.hpp>
#include <vrsph/core/uninitialized.hpp>
#include <vrsph/methods/vrsph/compact_rows.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>
#include <Eigen/LU>
#include <cmath>
#include <optional>
#include <set>
#include <utility>
#include <vrsph/methods/gradient_consistency.hpp>
#include <vrsph/methods/pair_mean.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/vrsph/vrsph.hpp>

namespace vrsph {

MethodInfo vrsph_info() {
  MethodInfo info{"vrsph",
          "[QW] §4-5",
          "volume-reconstruction SPH: per-particle NNLS volumes satisfying the moment conditions (4.1)/(4.2)",
          "O(h^3) gradient inside (gradient_order=3; [QW]'s rows O(h^2)), O(h^2) Laplacian on uniform, perturbed and "
          "centroid particles; O(h^2) Poisson (O(h^3) with the default compact rows); -L an M-matrix",
          {OperatorKind::Dx, OperatorKind::Dy, OperatorKind::Dz, OperatorKind::Gradient, OperatorKind::Laplacian,
           OperatorKind::DivAGrad},
          {{"nnls_tolerance", "NNLS tolerance; default 10 eps ||A||_1 max(m,n)"},
           {"nnls_max_iterations", "NNLS iteration cap; default 3 x neighbours"},
           {"rows", "merged (identical moment rows merged with sqrt(multiplicity) weights: same objective, "
                    "smaller system; default) | full (the literal 3/12/30 rows)"},
           {"profile", "default (our best correct rows: rhs and flux chosen by the use, see rhs/flux; default) | qw ([QW]'s "
                       "published rows everywhere: rhs=point, flux=gradient, boundary=nnls, prefer=none; what the "
                       "reproductions of [QW]'s tables pin; also gradient_order=2)"},
           {"boundary", "nnls (rows whose moment conditions no v >= 0 meets keep the NNLS best fit: [QW]; default) | "
                        "signed (such rows get exact moments with few, small negative volumes: second order up to "
                        "the wall, the M-matrix sign structure lost in those rows)"},
           {"flux", "auto (balance in a boundary value problem, gradient for operator values; default) | gradient "
                    "(Neumann/Robin rows a n.(G u) + beta u = q from VRSPH's gradient: [QW], first order) | balance (the "
                    "div(a grad) row at the wall particle with a wall-flux unknown c >= 0 in its first moments, "
                    "sum w x_ji = -c n: the row approximates div(a grad u) - c a du/dn and takes q as data; "
                    "monotone, second order)"},
           {"rhs", "auto (compact in a boundary value problem with mean=arithmetic, point for operator values and with "
                   "mean=harmonic; default) | point (the row "
                   "approximates div(a grad u) at x_i, right-hand side f_i: [QW]) | compact (a "
                   "generalised Mehrstellen row: w >= 0 and a positive average of f over the stencil (signed in the "
                   "rows of compact_fallback=signed), found together "
                   "so that the row is exact on polynomials of degree <= 4: O(h^3) truncation; "
                   "rows where none exists keep the point form; div-a-grad uses grad a when given, else FPM's "
                   "quadratic fit of a)"},
           {"compact_support", "compact rows: the fraction of the support radius whose neighbours each row tries "
                               "first, falling back to the whole support where they admit no positive row of degree "
                               "4 (default 0.8; 1: the whole support only, the rows before issue 37)"},
           {"compact_wide", "compact rows whose support admits no positive row of degree 4 (a few per 10^5 particles, "
                            "by the voids of a disordered cloud and by walls) try again over the particles within this "
                            "multiple of the support radius, and keep that row where it exists (default 1.25; 1: no "
                            "second try, the rows before)"},
           {"compact_select", "which of the many positive compact rows of a degree a row takes: truncation (default: "
                              "the one whose bound on the next degree's truncation error is least, by a linear program; "
                              "2-4 times more accurate on disordered clouds) | nnls (the one the NNLS path ends at, the "
                              "rows before)"},
           {"compact_degree", "compact rows: the polynomial degree each row tries first, 4 (default: O(h^4) solutions) | 6 "
                              "(2D Dirichlet problems: O(h^6), on Example 5 80-1300 times more accurate at n = 25-100 "
                              "for 4.5-8.5 times the stencil time; rows without a positive row of degree 6 over their support or the wider one "
                              "fall to the lower degrees, over the wider support first; in 3D 33-49 times the stencil "
                              "time of degree 4, and Neumann walls keep their lower-degree rows)"},
           {"compact_fallback", "compact rows whose degree 4 admits no w, mu >= 0 (a few by the walls and at voids "
                                "of a disordered cloud): signed (default: also degree 4 with w >= 0 and a signed "
                                "average mu, kept where its estimated truncation is below the positive degree-3 "
                                "row's; -L stays an M-matrix) | positive (the degree-3 row, the rows before)"},
           {"gradient_order", "3 (default: gradient, dx, dy, dz rows raised to exactness on cubics by the smallest "
                              "kernel-weighted change of [QW]'s row, O(h^3) inside; a row whose cubic fit is singular or "
                              "worse conditioned than 1e4 keeps [QW]'s row) | 2 ([QW]'s rows v_j grad W_ij: exact on "
                              "quadratics, O(h^2))"},
           {"prefer", "none (the NNLS columns as [QW]; default) | near (columns scaled by (r_min/r_j)^2: NNLS then "
                      "picks the nearest neighbours; same moments, a more compact row)"},
           pair_mean_option()}};
  info.profiles = {{"default", "rhs=auto flux=auto boundary=nnls prefer=none gradient_order=3: boundary value problems "
                                "get compact rows and balance Neumann rows (third/second order, -L an M-matrix), operator "
                                "values the point rows, gradients exact on cubics"},
                    {"qw", "rhs=point flux=gradient boundary=nnls prefer=none gradient_order=2: [QW] as "
                           "published"}};
  info.monotone = true;
  info.tensor_mobility = true;  // div(M grad u) by anisotropic moment targets (beyond [QW], docs/methods.md)
  return info;
}

namespace {

// Anisotropic targets for div(M grad u), M = diag(m_k): second moments 2 m_k(x_i) and first
// moments (∂_k m_k)(x_i), the latter from the kernel-corrected gradient Σ_j (m_j - m_i) A^-T ∇W
// (exact for linear m; A = Σ_j x_ji ⊗ ∇W_ij). A singular A leaves the first moments 0.
std::vector<MomentTarget> mobility_targets(const Discretisation& disc, const Eigen::MatrixXd& M, std::span<const char> rows) {
  const PointCloud& cloud = disc.cloud;
  const int dim = cloud.dim;
  std::vector<MomentTarget> t(static_cast<std::size_t>(cloud.size()));
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (rows.empty() ? cloud.tags[si] == Tag::Ghost : !rows[si]) continue;
    for (int k = 0; k < dim; ++k) t[si].second[k] = M(i, k);
    const Kernel ker = disc.kernel_at(i);
    const auto nbr = disc.neighbours.of(i);
    const auto dist = disc.neighbours.distances_of(i);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();  // column k: Σ (m_k,j - m_k,i) ∇W
    for (std::size_t n = 0; n < nbr.size(); ++n) {
      const Vec3 xji = cloud.positions[static_cast<std::size_t>(nbr[n])] - cloud.positions[si];
      const Vec3 g = -ker.dW_over_r(dist[n]) * xji;  // ∇_i W_ij points to j
      A += xji * g.transpose();
      for (int k = 0; k < dim; ++k) G.col(k) += (M(nbr[n], k) - M(i, k)) * g;
    }
    const Eigen::MatrixXd Ad = A.topLeftCorner(dim, dim);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(Ad);
    if (!lu.isInvertible()) continue;
    const Eigen::MatrixXd grad = lu.inverse().transpose() * G.topLeftCorner(dim, dim);  // column k: ∇m_k
    for (int k = 0; k < dim; ++k) t[si].first[k] = grad(k, k);
  }
  return t;
}

class Vrsph final : public Method {
 public:
  explicit Vrsph(const MethodOptions& o) : info_(vrsph_info()) {
    nnls_.tolerance = o.get_real("nnls_tolerance", -1);
    check<ConfigError>(nnls_.tolerance == -1 || nnls_.tolerance >= 0, "method option nnls_tolerance=", nnls_.tolerance,
                       " must be >= 0 (0: the tightest test; omit it for the default 10 eps ||A||_1 max(m, n))");
    // 0 iterations would stop every particle before its first volume: each row would be
    // empty and the solve would fail far away with a misleading connectivity error.
    nnls_.max_iterations = static_cast<int>(o.get_int("nnls_max_iterations", -1, 0, 1000000));
    check<ConfigError>(nnls_.max_iterations != 0,
                       "method option nnls_max_iterations=0 would stop the NNLS before it computes any volume "
                       "(every row empty); give >= 1, or omit it for the default 3 x neighbours");
    rows_ = o.get_choice("rows", "merged", {"merged", "full"}) == "merged" ? MomentRows::Merged : MomentRows::Full;
    mean_ = read_pair_mean(o);
    qw_ = o.get_choice("profile", "default", {"default", "qw"}) == "qw";
    // [QW]'s published rows: an option that says otherwise contradicts the profile.
    const auto pinned = [&](const char* key, const char* fallback, const std::set<std::string>& allowed,
                            const char* qw_value) {
      const std::string v = o.get_choice(key, qw_ ? qw_value : fallback, allowed);
      check<ConfigError>(!qw_ || v == qw_value, "method option ", key, "=", v, " contradicts profile=qw ([QW]'s rows are "
                         "rhs=point, flux=gradient, boundary=nnls, prefer=none, gradient_order=2); drop one of the two");
      return v;
    };
    signed_ = pinned("boundary", "nnls", {"nnls", "signed"}, "nnls") == "signed";
    flux_ = choice_of(pinned("flux", "auto", {"auto", "gradient", "balance"}, "gradient"));
    rhs_ = choice_of(pinned("rhs", "auto", {"auto", "point", "compact"}, "point"));
    near_ = pinned("prefer", "none", {"none", "near"}, "none") == "near";
    cubic_gradient_ = pinned("gradient_order", "3", {"2", "3"}, "2") == "3";
    signed_fallback_ = o.get_choice("compact_fallback", "signed", {"signed", "positive"}) == "signed";
    compact_support_ = o.get_real("compact_support", 0.8);
    compact_degree_ = o.get_choice("compact_degree", "4", {"4", "6"}) == "6" ? 6 : 4;
    wide_support_ = o.get_real("compact_wide", 1.25);
    least_truncation_ = o.get_choice("compact_select", "truncation", {"truncation", "nnls"}) == "truncation";
    check<ConfigError>(std::isfinite(wide_support_) && wide_support_ >= 1 && wide_support_ < 2, "method option "
                       "compact_wide must be a multiple in [1, 2) of the support radius (1: no wider support), got ",
                       wide_support_);
    check<ConfigError>(compact_support_ > 0 && compact_support_ <= 1, "method option compact_support must be a "
                       "fraction in (0, 1] of the support radius, got ", compact_support_);
  }
  const MethodInfo& info() const override { return info_; }
  bool balances_flux_rows(StencilUse use) const override { return resolve(flux_, use); }
  // Compact rows use grad a: better than the fit they fall back on.
  bool needs_coefficient_gradient(StencilUse use) const override { return compact_rows_for(use); }
  // compact_system: ∇a at the particles a row weighs, each fitted over its own support: 2
  // supports, 2.25 with the wider support (compact_wide = 1.25).
  Real estimated_gradient_reach() const override { return 1 + wide_support_; }
  // The wider support reaches compact_wide supports. (Its particles are found through the
  // neighbours' lists, and a neighbour's list holds every particle of the halo within its
  // support, so the halo need hold no more.)
  Real reach_for(StencilUse use) const override {
    return compact_rows_for(use) ? std::max<Real>(wide_support_, reach()) : reach();
  }
  // Point rows read pair vectors and distances only (moment systems, weights); compact rows,
  // balance rows and mobility targets read more of the cloud.
  bool reads_periodic_pairs(const StencilRequest& req) const override {
    const bool laplace = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;
    return req.mobility == nullptr && !(laplace && (compact_rows_for(req.use) || resolve(flux_, req.use)));
  }
  std::string row_forms(StencilUse use) const override {
    if (flux_ != Choice::Auto && rhs_ != Choice::Auto) return {};
    const bool system = use == StencilUse::System;
    std::string chosen;
    if (rhs_ == Choice::Auto) chosen = compact_rows_for(use) ? "rhs=compact" : "rhs=point";
    if (flux_ == Choice::Auto) chosen += std::string(chosen.empty() ? "" : ", ") + (system ? "flux=balance" : "flux=gradient");
    return detail::concat("vrsph: ", system ? "boundary value problem rows" : "point rows for operator values", " (",
                          chosen, system ? "; [QW]'s rows: profile=qw)"
                                         : "; boundary value problems default to rhs=compact, flux=balance)");
  }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    Stencil s;
    build_into(disc, req, s, nullptr);
    return s;
  }

  void rebuild(const Discretisation& disc, const StencilRequest& req, Stencil& out, std::unique_ptr<BuildState>& state,
               bool warm_start) const override {
    if (!dynamic_cast<VrsphBuildState*>(state.get())) state = std::make_unique<VrsphBuildState>();
    auto& st = static_cast<VrsphBuildState&>(*state);
    st.warm = warm_start;
    build_into(disc, req, out, &st);
  }

  void lend_volumes(std::unique_ptr<BuildState>& borrower, const BuildState* lender) const override {
    if (!dynamic_cast<VrsphBuildState*>(borrower.get())) borrower = std::make_unique<VrsphBuildState>();
    const auto* from = dynamic_cast<const VrsphBuildState*>(lender);
    static_cast<VrsphBuildState&>(*borrower).lender = from && from->lends ? from : nullptr;
  }

  Index borrowed_volume_rows(const BuildState* state) const override {
    const auto* st = dynamic_cast<const VrsphBuildState*>(state);
    return st ? st->borrowed_rows : 0;
  }

  std::pair<Index, Index> warm_start_counts(const BuildState* state) const override {
    const auto* st = dynamic_cast<const VrsphBuildState*>(state);
    return st ? std::pair{st->volumes.warm_rows, st->volumes.warm_hits} : std::pair<Index, Index>{0, 0};
  }

 private:
  // What a rebuild keeps: the volume arrays (their storage) and each row's NNLS passive set,
  // the next rebuild's warm start.
  struct VrsphBuildState final : BuildState {
    ReconstructedVolumes volumes;
    ActiveSets active;
    bool warm = true;
    // A Laplacian request's state: whether its last build's volumes are plain point volumes
    // under the Laplace conditions (no compact, balance or tensor rows), which a first-derivative
    // request of the same neighbour list may borrow (lend_volumes).
    bool lends = false;
    // A first-derivative request's state: the Laplacian's state to borrow from at the next
    // build (lend_volumes), cleared by that build.
    const VrsphBuildState* lender = nullptr;
    Index borrowed_rows = 0;  // rows of the last build whose volumes were borrowed
  };

  // build() and rebuild(): with a state, its arrays are reused and (warm) its active sets start
  // the NNLS and are replaced by this build's.
  void build_into(const Discretisation& disc, const StencilRequest& req, Stencil& s, VrsphBuildState* state) const {
    check_request(info_, disc, req, /*periodic_pairs=*/true);
    check<ConfigError>(disc.neighbours.shifts.empty() || reads_periodic_pairs(req), "vrsph: these rows (", 
                       req.mobility ? "a tensor mobility" : "compact or balance rows",
                       ") read positions beyond their pair vectors: on a periodic box build them with periodic_stencil(), "
                       "which gives them the periodic images");
    const bool laplace = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;
    const bool tensor = req.kind == OperatorKind::DivAGrad && req.mobility != nullptr;
    check<ConfigError>(!tensor || mean_ == PairMean::Arithmetic,
                       "vrsph: mean=harmonic applies to a scalar coefficient; with a tensor mobility the weights come "
                       "from anisotropic moment targets and have no pair coefficient (give the scalar a when K is "
                       "isotropic)");
    const std::vector<MomentTarget> targets = tensor ? mobility_targets(disc, *req.mobility, req.rows) : std::vector<MomentTarget>{};
    const auto& cloud = disc.cloud;
    VolumeOptions vo;
    vo.nnls = nnls_;
    vo.layout = rows_;
    vo.infeasible = signed_ ? InfeasibleRowPolicy::Signed : InfeasibleRowPolicy::Keep;
    vo.prefer_near = near_;
    // Balance rows: the requested Neumann particles of a Laplacian / div(a grad) request.
    std::vector<char> wall;
    std::vector<Vec3> conormal;
    const bool balance = resolve(flux_, req.use), compact = compact_rows_for(req.use);
    if (balance && laplace && balance_walls(cloud, req, tensor, wall, conormal)) vo.wall = {wall, conormal};
    // Compact rows first, written into the pattern; the point rows (their NNLS volumes) only
    // where no compact row exists: the point NNLS of a row that then takes the compact form
    // would be thrown away.
    // Without compact rows every row is written whole by point_weights (its zeros and its
    // diagonal included): the pattern's zero fill and the diagonal pass are saved (a sixth of a
    // rebuild on moving particles).
    const bool whole_rows = !(compact && laplace && !tensor);
    // A rebuild (moving particles) stores only the entries with a volume and the diagonal (about
    // a third of the pattern {i} ∪ N_i: NNLS keeps about one neighbour per moment row), so the
    // weights, their memory and every product with the stencil shrink alike. A fresh build keeps
    // the neighbour-list pattern that the rest of the library (rhs weights, studies) shares.
    // Cubic gradient rows spread their correction over every neighbour: the full pattern.
    const bool cubic = cubic_gradient_ && traits(req.kind).derivative_order == 1;
    const bool sparse = state && whole_rows && !cubic;
    if (!sparse) fill_stencil_pattern(disc.neighbours, req.kind, disc.cloud.dim, info_.name, s, !whole_rows);
    std::optional<CompactRows> compact_form;
    std::vector<char> point_rows;  // empty: every requested row
    if (compact && laplace && !tensor) {
      reserve_for_overwrite(s.rhs, s.col.size());
      s.rhs.assign(s.col.size(), 0.0);
      compact_form = compact_system(disc, req, wall, conormal, s);
      point_rows.assign(static_cast<std::size_t>(cloud.size()), 0);
      for (Index i = 0; i < cloud.size(); ++i)
        point_rows[static_cast<std::size_t>(i)] = row_requested(cloud, req, i) && !compact_form->ok[static_cast<std::size_t>(i)];
    }
    const std::span<const char> volume_rows = compact_form ? std::span<const char>(point_rows) : req.rows;
    ReconstructedVolumes fresh;
    ReconstructedVolumes& vol = state ? state->volumes : fresh;
    if (state && state->warm) {
      vo.warm_start = &state->active;
      vo.record_active = true;
    }
    // Borrowed volumes (moving particles, warm start only): a first-derivative row takes the
    // Laplacian's volumes where they meet the Laplace conditions, which contain its own: they
    // are an optimum of its NNLS (another vertex, as a warm start may give), and its own NNLS
    // is skipped. The other rows solve theirs.
    // A scalar div(a grad)'s point rows solve the Laplacian's very problem (the coefficient
    // enters only the weights, as a pair mean): they take all its volumes, and its active sets
    // as their next warm start.
    const VrsphBuildState* lender = state ? std::exchange(state->lender, nullptr) : nullptr;
    const bool takes_all = lender && state->warm && req.kind == OperatorKind::DivAGrad && !tensor && !compact_form &&
                           vo.wall.rows.empty() && !signed_ && req.rows.empty() &&
                           lender->volumes.conditions == MomentConditions::Laplace &&
                           lender->volumes.v.size() == static_cast<std::size_t>(disc.neighbours.total()) &&
                           lender->volumes.residual.size() == static_cast<std::size_t>(cloud.size());
    if (lender && !takes_all && (laplace || !state->warm)) lender = nullptr;
    std::vector<char> own_rows;
    if (takes_all) {
      take_volumes(lender->volumes, vol);
      vol.active = lender->active;
    } else {
      if (lender) own_rows = rows_not_borrowed(disc, req, lender->volumes, vo.signed_threshold);
      reconstruct_volumes(disc, laplace ? MomentConditions::Laplace : MomentConditions::Gradient,
                          lender ? std::span<const char>(own_rows) : volume_rows, vo, targets, vol);
    }
    if (state) {
      state->borrowed_rows = takes_all ? cloud.size() : lender ? borrow_volumes(disc, req, lender->volumes, own_rows, vol) : 0;
      state->lends = laplace && !tensor && !compact_form && vo.wall.rows.empty();
    }
    if (state && state->warm) std::swap(state->active, vol.active);  // this build's sets start the next
    if (tensor)  // residuals relative to |b| as for the Laplacian (|b| = sqrt(d)), so one tolerance serves both
      for (std::size_t i = 0; i < targets.size(); ++i) {
        const MomentTarget& t = targets[i];
        const Real bnorm = std::sqrt((0.5 * t.first).squaredNorm() + t.second.squaredNorm());
        if (bnorm > 0) vol.residual[i] *= std::sqrt(static_cast<Real>(disc.cloud.dim)) / bnorm;
      }
    if (sparse) sparse_pattern(disc, req, vol, s);
    point_weights(disc, req, vol, compact_form ? &point_rows : nullptr, tensor, whole_rows, sparse, s);
    s.residual = vol.residual;
    s.local_failure = vol.failed;
    s.wall_flux = std::move(vol.wall_flux);
    if (signed_) s.negative_volumes = std::move(vol.negative);
    if (compact_form) {
      store_compact_rows(*compact_form, disc, wall, s);
      replace_rows(s, compact_form->wide);  // the rows of the wider support: beyond the pattern
    }
    if (!whole_rows) set_difference_diagonal(s);
    if (cubic) {
      // A raised row meets every gradient moment condition (it is exact on cubics): its NNLS
      // residual no longer describes it, and a row the NNLS could not fit is not infeasible now.
      const GradientConsistencyReport raised = raise_to_cubic_exactness(disc, req, s);
      for (Index i = 0; i < cloud.size(); ++i) {
        const auto si = static_cast<std::size_t>(i);
        if (si < s.residual.size() && row_requested(cloud, req, i) &&
            !(si < s.local_failure.size() && s.local_failure[si]) &&
            !std::binary_search(raised.kept.begin(), raised.kept.end(), i))
          s.residual[si] = 0;
      }
    }
  }

  // The Neumann particles that take balance rows (wall) and their conormals (the unit
  // normal, times the mobility for a tensor). False when the request has none.
  static bool balance_walls(const PointCloud& cloud, const StencilRequest& req, bool tensor, std::vector<char>& wall,
                            std::vector<Vec3>& conormal) {
    wall.assign(static_cast<std::size_t>(cloud.size()), 0);
    bool any = false;
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      wall[si] = cloud.tags[si] == Tag::Neumann && (req.rows.empty() || req.rows[si]);
      any = any || wall[si];
    }
    if (!any) return false;
    check<InputError>(cloud.has_normals(), "vrsph flux=balance: the cloud has Neumann particles but no normals");
    conormal.assign(static_cast<std::size_t>(cloud.size()), Vec3::Zero());
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (!wall[si]) continue;
      const Vec3& nn = cloud.normals[si];
      check<InputError>(nn.allFinite() && nn.norm() > 0, "vrsph flux=balance: Neumann particle ", i,
                        " has no outward normal");
      conormal[si] = nn.normalized();
      if (tensor)
        for (int k = 0; k < cloud.dim; ++k) conormal[si][k] *= (*req.mobility)(i, k);
    }
    return true;
  }

  // Per particle: 1 where a first-derivative row of `req` solves its own NNLS, 0 where it
  // borrows the Laplace volumes `lent` (computed, positive, not signed, residual at most
  // `threshold` times |b| = sqrt(d): the moment conditions met to rounding).
  static std::vector<char> rows_not_borrowed(const Discretisation& disc, const StencilRequest& req,
                                             const ReconstructedVolumes& lent, Real threshold) {
    const PointCloud& cloud = disc.cloud;
    const auto n = static_cast<std::size_t>(cloud.size());
    std::vector<char> own(n, 0);
    const bool usable = lent.conditions == MomentConditions::Laplace &&
                        lent.v.size() == static_cast<std::size_t>(disc.neighbours.total()) && lent.residual.size() == n &&
                        lent.positive.size() == n && lent.failed.size() == n;
    const Real limit = threshold * std::sqrt(static_cast<Real>(cloud.dim));
    const NeighbourList& nl = disc.neighbours;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (!row_requested(cloud, req, i)) continue;
      bool lendable = usable && lent.positive[si] > 0 && !lent.failed[si] &&
                      (lent.signed_row.empty() || !lent.signed_row[si]) && lent.residual[si] <= limit;
      // Not where the support reaches a wall: there the Laplace volumes must also cancel the
      // first moments of a one-sided support, and the gradient's own NNLS, free of them, finds
      // volumes whose rows were measured more accurate (3D, n = 10: the flow's divergence 1.6 times
      // smaller at the worst row).
      for (const Index j : nl.of(i)) {
        const Tag t = cloud.tags[static_cast<std::size_t>(j)];
        lendable = lendable && t != Tag::Dirichlet && t != Tag::Neumann;
      }
      own[si] = lendable ? 0 : 1;
    }
    return own;
  }

  // Every row's volumes and their record (not the warm-start counts: no NNLS ran) into `vol`,
  // its storage reused.
  static void take_volumes(const ReconstructedVolumes& lent, ReconstructedVolumes& vol) {
    vol.conditions = lent.conditions;
    resize_for_overwrite(vol.v, lent.v.size());
    std::copy(lent.v.begin(), lent.v.end(), vol.v.begin());
    vol.residual = lent.residual;
    vol.failed = lent.failed;
    vol.iterations = lent.iterations;
    vol.positive = lent.positive;
    vol.signed_row = lent.signed_row;
    vol.negative = lent.negative;
    vol.wall_flux.clear();
    vol.warm_rows = vol.warm_hits = 0;
  }

  // The borrowed rows' volumes (rows_not_borrowed 0 and requested) copied into `vol`; returns
  // their count.
  static Index borrow_volumes(const Discretisation& disc, const StencilRequest& req, const ReconstructedVolumes& lent,
                              const std::vector<char>& own, ReconstructedVolumes& vol) {
    const PointCloud& cloud = disc.cloud;
    const NeighbourList& nl = disc.neighbours;
    Index borrowed = 0;
#pragma omp parallel for schedule(static) reduction(+ : borrowed)
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (own[si] || !row_requested(cloud, req, i)) continue;
      const Real* from = lent.v.data() + nl.offsets[si];
      std::copy(from, from + nl.count(i), vol.v.data() + nl.offsets[si]);
      vol.residual[si] = lent.residual[si];  // the Laplace residual bounds the gradient conditions' own
      vol.positive[si] = lent.positive[si];
      ++borrowed;
    }
    return borrowed;
  }

  // The pattern of a sparse rebuild: per row the requested row's neighbours with a volume and
  // the diagonal (rows not computed: the diagonal alone), values sized, not filled.
  void sparse_pattern(const Discretisation& disc, const StencilRequest& req, const ReconstructedVolumes& vol, Stencil& s) const {
    const PointCloud& cloud = disc.cloud;
    const NeighbourList& nl = disc.neighbours;
    const Index n = cloud.size();
    reset_stencil(s, req.kind, cloud.dim, info_.name);
    s.row_ptr.resize(static_cast<std::size_t>(n) + 1);
    s.diag.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      Index c = 1;
      if (row_requested(cloud, req, i)) {
        const Real* v = vol.v.data() + nl.offsets[static_cast<std::size_t>(i)];
        for (Index k = 0; k < nl.count(i); ++k) c += v[k] != 0 ? 1 : 0;
      }
      s.row_ptr[static_cast<std::size_t>(i) + 1] = c;
    }
    s.row_ptr[0] = 0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) s.row_ptr[i + 1] += s.row_ptr[i];
    reserve_for_overwrite(s.col, static_cast<std::size_t>(s.nnz()));
    s.col.resize(static_cast<std::size_t>(s.nnz()));
    s.values.resize(static_cast<std::size_t>(components(req.kind, cloud.dim)));
    for (auto& v : s.values) {
      reserve_for_overwrite(v, s.col.size());
      v.resize(s.col.size());
    }
  }

  // The point rows' weights from their reconstructed volumes: w_ij = v_j Y_ij for the
  // Laplacian (times the pair coefficient for div(a grad)), v_j grad_i W_ij for gradients.
  // point_rows: the rows without a compact form (null: every requested row).
  // whole_rows: every row is written whole, zeros and the difference-form diagonal included (the
  // pattern was not zero-filled); rows not computed get zeros and the diagonal -0 that
  // set_difference_diagonal gives them. Otherwise the zero slots are the pattern's. sparse: the
  // rows of sparse_pattern (columns written here).
  void point_weights(const Discretisation& disc, const StencilRequest& req, const ReconstructedVolumes& vol,
                     const std::vector<char>* point_rows, bool tensor, bool whole_rows, bool sparse, Stencil& s) const {
    const auto& cloud = disc.cloud;
#pragma omp parallel
    {
      std::optional<Kernel> ker;  // rebuilt only when the support radius changes (a pow per row otherwise)
      std::vector<Index> with_volume;  // point_row's scratch, grown to the longest row
#pragma omp for schedule(dynamic, 256)
      for (Index i = 0; i < cloud.size(); ++i) {
        const auto si = static_cast<std::size_t>(i);
        if (point_rows ? !(*point_rows)[si] : !row_requested(cloud, req, i)) {
          if (sparse) {
            s.col[static_cast<std::size_t>(s.row_begin(i))] = i;
            s.diag[si] = s.row_begin(i);
          }
          if (whole_rows) zero_row(s, i);
          continue;
        }
        if (!ker || ker->support() != disc.neighbours.radius(i)) ker = disc.kernel_at(i);
        const Real* v = vol.v.data() + disc.neighbours.offsets[si];
        const std::size_t count = neighbours_with_volume(v, static_cast<std::size_t>(disc.neighbours.count(i)), with_volume);
        if (sparse) sparse_row(disc, req, v, tensor, *ker, i, with_volume, count, s);
        else point_row(disc, req, v, tensor, *ker, i, whole_rows, with_volume, count, s);
      }
    }
  }

  static void zero_row(Stencil& s, Index i) {
    for (auto& v : s.values) {
      std::fill(v.begin() + s.row_begin(i), v.begin() + s.row_end(i), 0.0);
      v[static_cast<std::size_t>(s.diag[static_cast<std::size_t>(i)])] = -0.0;
    }
  }

  // The weight of pair (i, j) with volume vk and F_ij = W'/r into `slot` of every component.
  void write_pair(const Discretisation& disc, const StencilRequest& req, bool tensor, Index i, Index k, Real vk, Real f,
                  std::size_t slot, Stencil& s) const {
    const Index j = disc.neighbours.of(i)[static_cast<std::size_t>(k)];
    switch (req.kind) {
      case OperatorKind::Laplacian: s.values[0][slot] = -2 * vk * f; break;
      case OperatorKind::DivAGrad:
        s.values[0][slot] = tensor ? -2 * vk * f  // w = v Y with the anisotropic moment targets
                                   : -vk * pair_sum(mean_, (*req.coefficient)[i], (*req.coefficient)[j]) * f;
        break;
      default: {
        const Vec3 g = vk * f * (disc.cloud.positions[static_cast<std::size_t>(i)] - disc.neighbour_position(i, k));  // v_j grad_i W_ij
        if (req.kind == OperatorKind::Gradient)
          for (int c = 0; c < disc.cloud.dim; ++c) s.values[static_cast<std::size_t>(c)][slot] = g[c];
        else
          s.values[0][slot] = g[req.kind == OperatorKind::Dy ? 1 : req.kind == OperatorKind::Dz ? 2 : 0];
      }
    }
  }

  // Row i's weights from its volumes v (aligned with its neighbours). A neighbour without volume
  // (most of them: NNLS keeps about one per moment row) gets 0 (whole_rows) or keeps the
  // pattern's. whole_rows: the diagonal too, -Σ of the row in slot order as set_difference_diagonal
  // sums (the zeros left out of the sum change no bit: a sum of non-zero terms that starts at +0
  // is never -0). with_volume, count: neighbours_with_volume's. A whole row is zeroed as one
  // contiguous fill instead of slot by slot.
  void point_row(const Discretisation& disc, const StencilRequest& req, const Real* v, bool tensor, const Kernel& ker,
                 Index i, bool whole_rows, const std::vector<Index>& with_volume, std::size_t count, Stencil& s) const {
    const auto si = static_cast<std::size_t>(i);
    const std::size_t comps = s.values.size();
    const auto dist = disc.neighbours.distances_of(i);
    if (whole_rows)
      for (auto& values : s.values) std::fill(values.begin() + s.row_begin(i), values.begin() + s.row_end(i), 0.0);
    std::array<Real, 3> sum{0, 0, 0};
    for (std::size_t e = 0; e < count; ++e) {
      const Index k = with_volume[e];
      const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, k));
      write_pair(disc, req, tensor, i, k, v[k], ker.dW_over_r(dist[static_cast<std::size_t>(k)]), slot, s);
      if (whole_rows)
        for (std::size_t c = 0; c < comps; ++c) sum[c] += s.values[c][slot];
    }
    if (whole_rows)
      for (std::size_t c = 0; c < comps; ++c) s.values[c][static_cast<std::size_t>(s.diag[si])] = -sum[c];
  }

  // Row i's neighbours k with a volume (v[k] != 0) into with_volume (grown to the row),
  // ascending; their count. No branch per neighbour: which of them have a volume (about a
  // quarter in 2D) follows no pattern a branch predictor could learn.
  static std::size_t neighbours_with_volume(const Real* v, std::size_t n, std::vector<Index>& with_volume) {
    if (with_volume.size() < n) with_volume.resize(n);
    std::size_t found = 0;
    for (std::size_t k = 0; k < n; ++k) {
      with_volume[found] = static_cast<Index>(k);
      found += v[k] != 0 ? 1 : 0;
    }
    return found;
  }

  // The same into sparse_pattern's row: the neighbours with a volume, in column order with the
  // diagonal in its place (the neighbour rows are sorted), the diagonal -Σ of the others.
  void sparse_row(const Discretisation& disc, const StencilRequest& req, const Real* v, bool tensor, const Kernel& ker,
                  Index i, const std::vector<Index>& with_volume, std::size_t count, Stencil& s) const {
    const auto si = static_cast<std::size_t>(i);
    const std::size_t comps = s.values.size();
    const auto nbr = disc.neighbours.of(i);
    const auto dist = disc.neighbours.distances_of(i);
    std::array<Real, 3> sum{0, 0, 0};
    auto p = static_cast<std::size_t>(s.row_begin(i));
    bool diag_placed = false;
    for (std::size_t e = 0; e < count; ++e) {
      const auto k = static_cast<std::size_t>(with_volume[e]);
      if (!diag_placed && nbr[k] > i) {
        s.diag[si] = static_cast<Index>(p);
        s.col[p++] = i;
        diag_placed = true;
      }
      s.col[p] = nbr[k];
      write_pair(disc, req, tensor, i, static_cast<Index>(k), v[k], ker.dW_over_r(dist[k]), p, s);
      for (std::size_t c = 0; c < comps; ++c) sum[c] += s.values[c][p];
      ++p;
    }
    if (!diag_placed) {
      s.diag[si] = static_cast<Index>(p);
      s.col[p] = i;
    }
    for (std::size_t c = 0; c < comps; ++c) s.values[c][static_cast<std::size_t>(s.diag[si])] = -sum[c];
  }

  MethodInfo info_;
  NnlsOptions nnls_;
  MomentRows rows_ = MomentRows::Merged;
  PairMean mean_ = PairMean::Arithmetic;  // scalar coefficient only: the tensor path has no pair coefficient
  // An option's value; Auto resolves by StencilRequest::use (System: the second choice).
  enum class Choice { Auto, First, Second };
  static Choice choice_of(const std::string& v) {
    return v == "auto" ? Choice::Auto : (v == "balance" || v == "compact") ? Choice::Second : Choice::First;
  }
  static bool resolve(Choice c, StencilUse use) {
    return c == Choice::Second || (c == Choice::Auto && use == StencilUse::System);
  }
  // rhs=auto: compact rows in a boundary value problem, unless mean=harmonic says the
  // coefficient is rough: the compact rows are exact on a smooth a (degree 4 with grad a), and
  // across jumps the harmonic pair mean of the point rows is the better row (docs/methods.md).
  bool compact_rows_for(StencilUse use) const {
    return rhs_ == Choice::Auto ? use == StencilUse::System && mean_ == PairMean::Arithmetic : rhs_ == Choice::Second;
  }
  bool qw_ = false;       // profile=qw
  bool signed_ = false;   // boundary=signed
  Choice flux_ = Choice::Auto;  // gradient | balance
  Choice rhs_ = Choice::Auto;   // point | compact
  bool near_ = false;     // prefer=near
  bool cubic_gradient_ = true;  // gradient_order=3
  Real compact_support_ = 0.8;  // compact rows: the inner neighbours tried first (fraction of h)
  int compact_degree_ = 4;       // compact rows: the degree tried first
  bool signed_fallback_ = true;  // compact_fallback=signed: rows without a positive degree-4 row
  Real wide_support_ = 1.25;     // compact_wide: their second try's support (multiple of h)
  bool least_truncation_ = true;  // compact_select=truncation: the row of least truncation bound (a linear program)

  // The compact (Mehrstellen) form of every requested row that admits one (CompactRows::ok).
  // Balance (wall) rows take the compact form too where it exists, with the wall flux c_i
  // of the compact system (conormal: the unit n_i of the balance rows).
  CompactRows compact_system(const Discretisation& disc, const StencilRequest& req, const std::vector<char>& wall,
                             const std::vector<Vec3>& conormal, Stencil& s) const {
    const PointCloud& cloud = disc.cloud;
    const bool divagrad = req.kind == OperatorKind::DivAGrad;
    // ∇a: given (the studies sample it from the expression of a), zero for a constant a, else
    // estimated by FPM's quadratic fit (second order: the rows then keep O(h^2) where a varies).
    Eigen::MatrixXd estimated;
    const Eigen::MatrixXd* grad_a = req.coefficient_gradient;
    std::vector<char> rows(static_cast<std::size_t>(cloud.size()), 0);
    for (Index i = 0; i < cloud.size(); ++i) rows[static_cast<std::size_t>(i)] = row_requested(cloud, req, i);
    if (divagrad && !grad_a) {
      const Field& a = *req.coefficient;
      estimated = Eigen::MatrixXd::Zero(cloud.size(), cloud.dim);
      if (a.size() > 0 && a.maxCoeff() != a.minCoeff()) {
        // A row whose quadratic fit is singular (too few or one-sided neighbours: small knn
        // supports, a hole's rim) has no grad a: it keeps the point form rather than fail.
        MethodOptions fit;
        fit.set("gradient_order", "2");
        fit.set("on_singular", "warn");
        StencilRequest greq;
        greq.kind = OperatorKind::Gradient;
        const Stencil g = builtin_methods().create("fpm", fit)->build(disc, greq);
        estimated = apply(g, a);
        for (std::size_t i = 0; i < g.local_failure.size(); ++i)
          if (g.local_failure[i]) rows[i] = 0;
      }
      grad_a = &estimated;
    }
    std::vector<Vec3> flux_direction;  // a_i n_i: the compact row's flux term is c_i (a n·∇u)_i
    CompactWalls walls;
    if (!conormal.empty()) {
      flux_direction = conormal;
      if (divagrad)
        for (Index i = 0; i < cloud.size(); ++i) flux_direction[static_cast<std::size_t>(i)] *= (*req.coefficient)[i];
      walls = {wall, flux_direction};
    }
    CompactRowOptions co;
    co.tolerance = kCompactTolerance;
    co.inner_support = compact_support_;
    co.signed_average = signed_fallback_;
    co.wide_support = wide_support_;
    co.least_truncation = least_truncation_;
    co.degree = compact_degree_;
    co.wide_lower_degrees = compact_degree_ > 4;
    return compact_rows(disc, rows, divagrad ? req.coefficient : nullptr, divagrad ? grad_a : nullptr, co, s, walls);
  }

  // Completes the compact rows (their weights are in place): the right-hand-side weight of
  // the diagonal, μ_ii (δ_ii = 1 for the rows that keep the point form), and each compact
  // row's residual, wall flux and diagnostics.
  void store_compact_rows(const CompactRows& c, const Discretisation& disc, const std::vector<char>& wall, Stencil& s) const {
    const PointCloud& cloud = disc.cloud;
    for (Index i = 0; i < cloud.size(); ++i) {
      const auto si = static_cast<std::size_t>(i);
      const auto d = static_cast<std::size_t>(s.diag[si]);
      if (!c.ok[si]) {
        s.rhs[d] = 1;
        continue;
      }
      s.rhs[d] = c.mu_self[si];
      if (!c.wall_flux.empty() && wall[si]) s.wall_flux[si] = c.wall_flux[si];
      // The row's local problem is now the compact one (|b| = 1): its residual, on the
      // scale the summaries use (relative residual x sqrt(d)).
      s.residual[si] = c.residual[si] * std::sqrt(static_cast<Real>(cloud.dim));
      if (!s.negative_volumes.empty()) s.negative_volumes[si] = 0;
      if (!s.local_failure.empty()) s.local_failure[si] = 0;
    }
  }
  // Relative residual of the scaled compact system below which a row takes the compact form.
  // A residual r costs a truncation error ~ r |grad u| / h against ~ h^2 |D^4 u| for the
  // point form it would fall back on; NNLS stops at ~2e-10 on ~1% of the rows of an exact
  // lattice (one column short, which its multiplier test does not admit), and 1e-8 keeps
  // those rows compact to h ~ 1e-3.
  static constexpr Real kCompactTolerance = 1e-8;
};

}  // namespace

std::unique_ptr<Method> make_vrsph(const MethodOptions& options) { return std::make_unique<Vrsph>(options); }

}  // namespace vrsph
