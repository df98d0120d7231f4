// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/pair_mean.hpp>
#include <vrsph/methods/spe/ingredients.hpp>
#include <vrsph/methods/spe/spe.hpp>
#include <vrsph/methods/taylor/local_system.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

NeighbourList symmetrised_pairs(const PointCloud& cloud, const NeighbourList& nl) {
  const Real hmax = *std::max_element(nl.radii.begin(), nl.radii.end());
  SearchParams sp;
  sp.radii.resize(nl.radii.size());
  for (std::size_t i = 0; i < nl.radii.size(); ++i) sp.radii[i] = 0.5 * (nl.radii[i] + hmax);
  sp.radius = hmax;
  sp.min_neighbours = 0;  // the caller's search has checked the counts already
  const NeighbourList wide = find_neighbours(cloud, sp);
  NeighbourList out;
  out.radii = nl.radii;
  out.offsets.assign(static_cast<std::size_t>(wide.size()) + 1, 0);
  std::vector<Index> idx;
  std::vector<Real> dist;
  for (Index i = 0; i < wide.size(); ++i) {
    const auto nbr = wide.of(i);
    const auto d = wide.distances_of(i);
    for (std::size_t k = 0; k < nbr.size(); ++k)
      if (d[k] < 0.5 * (nl.radius(i) + nl.radius(nbr[k]))) {
        idx.push_back(nbr[k]);
        dist.push_back(d[k]);
      }
    out.offsets[static_cast<std::size_t>(i) + 1] = static_cast<Index>(idx.size());
  }
  out.indices.assign(idx.begin(), idx.end());
  out.distances.assign(dist.begin(), dist.end());
  return out;
}

namespace {

enum class Scheme { Brookshaw, CorrectedBrookshaw, Schwaiger, Monotone };
enum class Anisotropy { Consistent, Paper };

using spe::GradientOption;
using spe::RowGeometry;
using spe::RowIngredients;
using taylor::SmallMatrix;
using taylor::SmallVector;

bool radii_differ(const NeighbourList& nl) {
  return std::any_of(nl.radii.begin(), nl.radii.end(), [&](Real h) { return h != nl.radii.front(); });
}

// Mobility of particle i in direction k: tensor, scalar coefficient, or 1 (Laplacian).
struct Mobility {
  const Eigen::MatrixXd* tensor = nullptr;
  const Field* scalar = nullptr;
  Real operator()(Index i, int k) const {
    return tensor ? (*tensor)(i, k) : scalar ? (*scalar)[i] : 1.0;
  }
};

// The consistent anisotropic weights (spe.hpp): per direction k, c^k_J = β_J φ(J)·θ_k with
// φ = (e_a e_b for a <= b, Δ_a/h), θ_k from the moment conditions. Returns the relative
// residual of the conditions (0 when they are met) and fills coef (dim x p).
struct ConsistentCorrection {
  int dim = 2, p = 5;
  SmallMatrix theta;  // p x dim

  static int basis_size(int d) { return d * (d + 1) / 2 + d; }
  static void basis(const Vec3& delta, Real r, Real h, int d, Real* phi) {
    int m = 0;
    for (int a = 0; a < d; ++a)
      for (int b = a; b < d; ++b) phi[m++] = delta[a] * delta[b] / (r * r);
    for (int a = 0; a < d; ++a) phi[m++] = delta[a] / h;
  }
  // Conditions: first moments Δ_a/h (d rows), second moments Δ_aΔ_b/h² (a <= b).
  static void conditions(const Vec3& delta, Real h, int d, Real* mu) {
    int m = 0;
    for (int a = 0; a < d; ++a) mu[m++] = delta[a] / h;
    for (int a = 0; a < d; ++a)
      for (int b = a; b < d; ++b) mu[m++] = delta[a] * delta[b] / (h * h);
  }

  Real solve(const RowGeometry& row, const std::vector<Real>& beta, Real h) {
    const int d = row.dim;
    p = basis_size(d);
    SmallMatrix Q = SmallMatrix::Zero(p, p);
    Real phi[9], mu[9];
    for (std::size_t k = 0; k < row.size(); ++k) {
      basis(row.delta[k], row.r[k], h, d, phi);
      conditions(row.delta[k], h, d, mu);
      for (int c = 0; c < p; ++c)
        for (int m = 0; m < p; ++m) Q(c, m) += beta[k] * mu[c] * phi[m];
    }
    SmallMatrix rhs = SmallMatrix::Zero(p, d);
    for (int k = 0, m = d; k < d; ++k) {  // the (k,k) second-moment row
      rhs(m, k) = 1;
      m += d - k;
    }
    // Columns scaled to unit norm; rank-revealing least squares keeps sparse supports
    // (e.g. only the 2d face neighbours, where e_x e_y vanishes) solvable.
    SmallVector scale(p);
    for (int m = 0; m < p; ++m) {
      const Real nrm = Q.col(m).norm();
      scale[m] = nrm > 0 ? 1 / nrm : 0;
    }
    const SmallMatrix Qs = Q * scale.asDiagonal();
    Eigen::CompleteOrthogonalDecomposition<SmallMatrix> cod(Qs);
    cod.setThreshold(1e-10);
    theta = scale.asDiagonal() * cod.solve(rhs);
    if (!theta.allFinite()) return std::numeric_limits<Real>::infinity();
    theta /= h * h;  // the second-moment rows were written in Δ/h
    const Real res = (Q * theta * (h * h) - rhs).norm() / std::sqrt(static_cast<Real>(d));
    return std::isfinite(res) ? res : std::numeric_limits<Real>::infinity();
  }

  // c^k_J for neighbour J (k < dim).
  Real weight(const RowGeometry& row, std::size_t J, Real beta, Real h, int k) const {
    Real phi[9];
    basis(row.delta[J], row.r[J], h, row.dim, phi);
    Real s = 0;
    for (int m = 0; m < p; ++m) s += theta(m, k) * phi[m];
    return beta * s;
  }
};

class SpeScheme final : public Method {
 public:
  SpeScheme(MethodInfo info, Scheme scheme, const MethodOptions& o)
      : info_(std::move(info)), scheme_(scheme),
        gradient_(spe::parse_gradient_option(o.get_choice("gradient", "g1", {"g1", "g2", "g3", "g4"}))),
        anisotropy_(o.get_choice("anisotropy", "consistent", {"consistent", "paper"}) == "paper" ? Anisotropy::Paper
                                                                                                 : Anisotropy::Consistent),
        corrected_pair_(o.get_choice("pair_gradient", "plain", {"plain", "corrected"}) == "corrected"),
        volume_(o.get_choice("volume", "dx", {"dx", "shepard"})), policy_(taylor::read_singular_policy(o)),
        mean_(read_pair_mean(o)) {}
  const MethodInfo& info() const override { return info_; }
  // Shepard volumes sum each neighbour's own list: one more ring of particles than the rows
  // (a rank's halo, a periodic box's images; with one ring the halo's last volumes were short).
  int reach() const override { return info().stencil_rings + (volume_ == "shepard" ? 1 : 0); }

  Stencil build(const Discretisation& disc, const StencilRequest& req) const override {
    check_request(info_, disc, req);
    const auto& cloud = disc.cloud;
    const Index n = cloud.size();
    Build b{disc, req, taylor::method_volumes(disc, volume_), {}, radii_differ(disc.neighbours), nullptr, {}};
    if (b.symmetrise) b.own = symmetrised_pairs(cloud, disc.neighbours);
    b.nl = b.symmetrise ? &b.own : &disc.neighbours;
    Stencil s = make_stencil_pattern(*b.nl, req.kind, cloud.dim, info_.name);
    s.condition.assign(static_cast<std::size_t>(n), 0);
    const bool second = req.kind == OperatorKind::Laplacian || req.kind == OperatorKind::DivAGrad;
    if (second) s.xi.assign(static_cast<std::size_t>(n), 0);
    if (second) s.residual.assign(static_cast<std::size_t>(n), 0);
    b.mob = Mobility{req.mobility, req.kind == OperatorKind::DivAGrad ? req.coefficient : nullptr};
#pragma omp parallel
    {
      Scratch t;
      t.row.dim = cloud.dim;
#pragma omp for schedule(dynamic, 128)
      for (Index i = 0; i < n; ++i) {
        if (!taylor::wants_row(cloud, req, i)) continue;
        if (!row_ingredients(b, i, t, s)) continue;
        if (second) second_order_row(b, i, t, s);
        else gradient_row(b, i, t, s);
      }
    }
    set_difference_diagonal(s);
    taylor::enforce_condition(s, policy_, cloud);
    return s;
  }

 private:
  // What every row of one build reads.
  struct Build {
    const Discretisation& disc;
    const StencilRequest& req;
    std::vector<Real> V;  ///< particle volumes
    NeighbourList own;    ///< symmetrised pairs when the radii differ
    bool symmetrise;
    const NeighbourList* nl;
    Mobility mob;
  };
  // Per thread: the row's geometry and the scheme's ingredients.
  struct Scratch {
    RowGeometry row;
    RowIngredients in;
    std::vector<Real> beta;
    Eigen::Matrix3d gamma_star;
    ConsistentCorrection corr;
  };

  // The row's geometry and the scheme's ingredients (renormalised gradients, moments);
  // false for a row whose ingredients are singular (its condition says so).
  bool row_ingredients(const Build& b, Index i, Scratch& t, Stencil& s) const {
    const auto& cloud = b.disc.cloud;
    const auto si = static_cast<std::size_t>(i);
    const auto nbr = b.nl->of(i);
    const Vec3& xi = cloud.positions[si];
    const Real hi = b.nl->radius(i);
    const Kernel self_kernel(b.disc.kernel, cloud.dim, hi);
    RowGeometry& row = t.row;
    row.resize(nbr.size());
    row.volume_self = b.V[si];
    row.W_self = self_kernel.W(0);
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const auto sj = static_cast<std::size_t>(nbr[k]);
      row.delta[k] = cloud.positions[sj] - xi;
      row.r[k] = row.delta[k].norm();
      row.volume[k] = b.V[sj];
      const Kernel pair = b.symmetrise ? Kernel(b.disc.kernel, cloud.dim, 0.5 * (hi + b.nl->radius(nbr[k]))) : self_kernel;
      row.W[k] = pair.W(row.r[k]);
      row.dW_over_r[k] = pair.dW_over_r(row.r[k]);
    }
    spe::compute_ingredients(row, gradient_, t.in);
    s.condition[si] = t.in.condition;
    return std::isfinite(t.in.condition);
  }

  // First-derivative rows: V_J g*_J (one component, or every one for the gradient).
  void gradient_row(const Build& b, Index i, const Scratch& t, Stencil& s) const {
    const OperatorKind kind = b.req.kind;
    const int axis = kind == OperatorKind::Dy ? 1 : kind == OperatorKind::Dz ? 2 : 0;
    for (std::size_t k = 0; k < b.nl->of(i).size(); ++k) {
      const auto slot = static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)));
      const Vec3 g = t.row.volume[k] * t.in.gstar[k];
      if (kind == OperatorKind::Gradient)
        for (int c = 0; c < t.row.dim; ++c) s.values[static_cast<std::size_t>(c)][slot] = g[c];
      else
        s.values[0][slot] = g[axis];
    }
  }

  // The scheme's bracket (unit mobility): the vector X it subtracts and its multiplier.
  void scheme_bracket(Scratch& t, Vec3& X, Real& factor) const {
    const int dim = t.row.dim;
    X = Vec3::Zero();
    factor = 1;
    switch (scheme_) {
      case Scheme::Brookshaw: break;
      case Scheme::CorrectedBrookshaw: factor = spe::trace_of_inverse_over_dim(t.in.A, dim); break;
      case Scheme::Schwaiger:
        X = t.in.N;
        factor = spe::trace_of_inverse_over_dim(t.in.Gamma, dim);
        break;
      case Scheme::Monotone: {
        X = t.in.Ntilde;
        spe::monotone_transmissibilities(t.row, t.in, t.beta, t.gamma_star);
        const bool admissible = spe::gamma_star_admissible(t.gamma_star, t.in.Gamma, dim);
        factor = spe::trace_of_inverse_over_dim(admissible ? t.gamma_star : t.in.Gamma, dim);
        break;
      }
    }
  }

  // With only d neighbours in general position the first-moment correction annihilates the
  // whole bracket (Σ T̄ Δ = 0 forces T̄ = 0), leaving round-off of either sign. Such a row
  // falls back to the uncorrected pair term (the Brookshaw bracket, monotone) and is
  // reported as infeasible (residual 1) so that the studies count and name it.
  Real drop_degenerate_correction(const Scratch& t, std::size_t neighbours, Vec3& X) const {
    if (X.squaredNorm() == 0) return 0;
    Real kept = 0, scale = 0;
    for (std::size_t k = 0; k < neighbours; ++k) {
      const Real pair = pair_term(t.row, t.in, k);
      kept += std::abs(t.row.volume[k] * (pair - X.dot(t.in.gstar[k])));
      scale += std::abs(t.row.volume[k] * pair);
    }
    if (kept > 1e-6 * scale) return 0;
    X.setZero();
    return 1;
  }

  // Second-derivative rows: the scheme's bracket with the pair mobilities, printed or with
  // the consistent anisotropic correction.
  void second_order_row(const Build& b, Index i, Scratch& t, Stencil& s) const {
    const auto si = static_cast<std::size_t>(i);
    const auto nbr = b.nl->of(i);
    const int dim = t.row.dim;
    Vec3 X;
    Real factor = 1;
    scheme_bracket(t, X, factor);
    Real reach = -std::numeric_limits<Real>::infinity();
    for (std::size_t k = 0; k < nbr.size(); ++k) reach = std::max(reach, t.in.xi.dot(t.row.delta[k]));
    s.xi[si] = nbr.empty() ? 0 : reach;
    if (!std::isfinite(factor) || factor <= 0) {
      s.condition[si] = std::numeric_limits<Real>::infinity();
      return;
    }
    const Real degenerate = drop_degenerate_correction(t, nbr.size(), X);
    s.residual[si] = degenerate;
    if (b.req.mobility && anisotropy_ == Anisotropy::Consistent) {
      t.beta.resize(nbr.size());
      for (std::size_t k = 0; k < nbr.size(); ++k)
        t.beta[k] = t.row.volume[k] * (pair_term(t.row, t.in, k) - X.dot(t.in.gstar[k]));
      const Real res = t.corr.solve(t.row, t.beta, b.nl->radius(i));
      s.residual[si] = std::max(res, degenerate);
      if (!std::isfinite(res)) {
        s.condition[si] = res;
        return;
      }
      for (std::size_t k = 0; k < nbr.size(); ++k) {
        Real w = 0;
        for (int c = 0; c < dim; ++c)
          w += t.corr.weight(t.row, k, t.beta[k], b.nl->radius(i), c) * pair_sum(mean_, b.mob(i, c), b.mob(nbr[k], c));
        s.values[0][static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)))] = w;
      }
      return;
    }
    // Printed form: (m_I + m_J) a·b becomes aᵀ(M_I + M_J) b in both terms (§3.7.5).
    for (std::size_t k = 0; k < nbr.size(); ++k) {
      const Vec3& D = t.row.delta[k];
      const Vec3& gp = corrected_pair_ ? t.in.gstar[k] : t.in.g[k];
      Real w = 0;
      for (int c = 0; c < dim; ++c) {
        const Real mbar = pair_sum(mean_, b.mob(i, c), b.mob(nbr[k], c));
        w += mbar * (D[c] * gp[c] / (t.row.r[k] * t.row.r[k]) - X[c] * t.in.gstar[k][c]);
      }
      s.values[0][static_cast<std::size_t>(neighbour_slot(s, i, static_cast<Index>(k)))] = factor * t.row.volume[k] * w;
    }
  }

  // The pair term Δ·g/r² of the bracket, or Δ·g*/r² with pair_gradient=corrected.
  Real pair_term(const RowGeometry& row, const RowIngredients& in, std::size_t k) const {
    return corrected_pair_ ? row.delta[k].dot(in.gstar[k]) / (row.r[k] * row.r[k]) : in.radial[k];
  }

  MethodInfo info_;
  Scheme scheme_;
  GradientOption gradient_;
  Anisotropy anisotropy_;
  bool corrected_pair_;  // Δ·g*/r² in the pair term ([SPE] Figs. 1-2 "corrected kernel ∇*W")
  std::string volume_;
  taylor::SingularPolicy policy_;
  PairMean mean_;
};

MethodInfo spe_info(std::string name, std::string description, std::string claimed, bool monotone) {
  MethodInfo info{std::move(name),
                  "[SPE] §3",
                  std::move(description),
                  std::move(claimed),
                  {OperatorKind::Dx, OperatorKind::Dy, OperatorKind::Dz, OperatorKind::Gradient, OperatorKind::Laplacian,
                   OperatorKind::DivAGrad},
                  {}};
  info.options = {{"gradient", "kernel gradient g1 (15, default) | g2 (16) | g3 (17) | g4 (18)"},
                  {"anisotropy", "consistent (default: exact on quadratics for constant diagonal M) | paper (the "
                                 "printed pair weight, inconsistent when m_1 != m_2, docs/methods.md); tensor mobility only"},
                  {"pair_gradient", "plain (default: Δ·g/r²) | corrected (Δ·g*/r², the \"corrected kernel\" of [SPE] "
                                    "Figs. 1-2)"},
                  pair_mean_option()};
  for (auto& o : taylor::corrected_method_options()) info.options.push_back(o);
  info.tensor_mobility = true;
  info.monotone = monotone;
  return info;
}

}  // namespace

MethodInfo brookshaw_info() {
  return spe_info("brookshaw", "Brookshaw two-point-flux scheme [SPE](27) (Morris with g1 and a scalar coefficient)",
                  "not consistent on disordered particles (leading error 2m ∇u·N, [SPE](32)); monotone", true);
}
MethodInfo cb_sph_info() {
  return spe_info("cb-sph", "corrected Brookshaw [SPE](51): Brookshaw times tr(A^-1)/d",
                  "C Δx^ω/h̃ + O(h̃²), 0 <= ω < 2 ([SPE] Thm 1); monotone for radial gradients", true);
}
MethodInfo s_sph_info() {
  return spe_info("s-sph", "Schwaiger's scheme [SPE](52)-(55): corrected-gradient bracket times tr(Γ^-1)/d",
                  "C Δx^ω/h̃, 1 <= ω < 2 far from the boundary ([SPE] Thm 2); exact on quadratics on lattices; "
                  "not monotone", false);
}
MethodInfo m_sph_info() {
  return spe_info("m-sph", "the monotone M-SPH scheme [SPE](69)-(73), transmissibility form (90)-(91), Γ* with "
                  "the admissibility fallback of [SPE] §3 (docs/methods.md)",
                  "C Δx^ω/h̃, 1 <= ω < 2 far from the boundary ([SPE] Thm 3); equals S-SPH on lattices; "
                  "monotone where (92)/(93) hold", true);
}
std::unique_ptr<Method> make_brookshaw(const MethodOptions& o) {
  return std::make_unique<SpeScheme>(brookshaw_info(), Scheme::Brookshaw, o);
}
std::unique_ptr<Method> make_cb_sph(const MethodOptions& o) {
  return std::make_unique<SpeScheme>(cb_sph_info(), Scheme::CorrectedBrookshaw, o);
}
std::unique_ptr<Method> make_s_sph(const MethodOptions& o) {
  return std::make_unique<SpeScheme>(s_sph_info(), Scheme::Schwaiger, o);
}
std::unique_ptr<Method> make_m_sph(const MethodOptions& o) {
  return std::make_unique<SpeScheme>(m_sph_info(), Scheme::Monotone, o);
}

}  // namespace vrsph
