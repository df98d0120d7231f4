// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/spe/ingredients.hpp>

namespace vrsph::spe {

namespace {
// Inverse of the top-left d x d block (d <= 3) after row and column equilibration, in
// closed form (the per-particle hot path: no dynamic allocation, no pivoting loop); returns
// the 1-norm condition number of the equilibrated block, +inf if it is singular.
Real small_inverse(const Eigen::Matrix3d& M, int d, Eigen::Matrix3d& inv) {
  inv.setZero();
  Vec3 r = Vec3::Ones(), c = Vec3::Ones();
  for (int i = 0; i < d; ++i) {
    const Real m = M.row(i).head(d).cwiseAbs().maxCoeff();
    if (!(m > 0) || !std::isfinite(m)) return std::numeric_limits<Real>::infinity();
    r[i] = 1 / m;
  }
  Eigen::Matrix3d E = r.asDiagonal() * M;
  for (int j = 0; j < d; ++j) {
    const Real m = E.col(j).head(d).cwiseAbs().maxCoeff();
    if (!(m > 0)) return std::numeric_limits<Real>::infinity();
    c[j] = 1 / m;
  }
  E = E * c.asDiagonal();
  Eigen::Matrix3d Einv = Eigen::Matrix3d::Zero();
  Real det = 0;
  if (d == 1) {
    det = E(0, 0);
    Einv(0, 0) = 1 / det;
  } else if (d == 2) {
    const Eigen::Matrix2d e = E.topLeftCorner<2, 2>();
    det = e.determinant();
    Einv.topLeftCorner<2, 2>() = e.inverse();
  } else {
    det = E.determinant();
    Einv = E.inverse();
  }
  if (!(std::abs(det) > 1e-300) || !Einv.allFinite()) return std::numeric_limits<Real>::infinity();
  const auto norm1 = [d](const Eigen::Matrix3d& X) { return X.topLeftCorner(d, d).cwiseAbs().colwise().sum().maxCoeff(); };
  const Real cond = norm1(E) * norm1(Einv);
  inv = c.asDiagonal() * Einv * r.asDiagonal();  // M = R^-1 E C^-1
  return std::isfinite(cond) ? cond : std::numeric_limits<Real>::infinity();
}
}  // namespace

GradientOption parse_gradient_option(const std::string& name) {
  if (name == "g1") return GradientOption::G1;
  if (name == "g2") return GradientOption::G2;
  if (name == "g3") return GradientOption::G3;
  if (name == "g4") return GradientOption::G4;
  throw ConfigError("unknown gradient option '" + name + "' (known: g1, g2, g3, g4; [SPE](15)-(18))");
}

void compute_ingredients(const RowGeometry& row, GradientOption option, RowIngredients& out) {
  const int d = row.dim;
  const std::size_t n = row.size();
  out.g.resize(n);
  out.gstar.resize(n);
  out.radial.resize(n);
  // Shepard sum (13) and its gradient: ν = V_I W(0) + Σ V_J W_IJ, ∇ν = Σ V_J g⁰_IJ.
  Real nu = row.volume_self * row.W_self;
  Vec3 grad_nu = Vec3::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 g0 = -row.dW_over_r[k] * row.delta[k];
    out.g[k] = g0;
    nu += row.volume[k] * row.W[k];
    grad_nu += row.volume[k] * g0;
  }
  out.nu = nu;
  if (option != GradientOption::G1) {
    const Real inv = nu > 0 ? 1 / nu : 0;
    for (std::size_t k = 0; k < n; ++k) {
      Vec3& g = out.g[k];
      switch (option) {
        case GradientOption::G2: g = g * inv - row.W[k] * grad_nu * inv * inv; break;       // (16)
        case GradientOption::G3: g = g * inv; break;                                        // (17)
        case GradientOption::G4: g = g * inv * (1 - row.volume[k] * row.W[k] * inv); break;  // (18)
        case GradientOption::G1: break;
      }
    }
  }
  out.A.setZero();
  out.Gamma.setZero();
  out.N.setZero();
  out.Ntilde.setZero();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& D = row.delta[k];
    const Vec3& g = out.g[k];
    const Real V = row.volume[k];
    out.radial[k] = D.dot(g) / (row.r[k] * row.r[k]);
    out.A += V * D * g.transpose();                    // A_ab = Σ V Δ_a g_b
    out.N += V * g;                                    // (53)
    out.Ntilde += V * out.radial[k] * D;               // (65)
    out.Gamma += V * out.radial[k] * D * D.transpose();  // (55)
  }
  // C = A^-T (METHODS R4: (24)'s A^-1 satisfies (25) only for symmetric A).
  Eigen::Matrix3d Ainv;
  out.condition = small_inverse(out.A, d, Ainv);
  out.C.setZero();
  if (std::isfinite(out.condition)) out.C.topLeftCorner(d, d) = Ainv.topLeftCorner(d, d).transpose();
  for (std::size_t k = 0; k < n; ++k) out.gstar[k] = out.C * out.g[k];
  out.xi = out.C.transpose() * out.Ntilde;  // (94)
}

void monotone_transmissibilities(const RowGeometry& row, const RowIngredients& in, std::vector<Real>& T,
                                 Eigen::Matrix3d& gamma_star) {
  T.resize(row.size());
  gamma_star.setZero();
  for (std::size_t k = 0; k < row.size(); ++k) {
    T[k] = row.volume[k] * (in.radial[k] - in.Ntilde.dot(in.gstar[k]));
    gamma_star += T[k] * row.delta[k] * row.delta[k].transpose();
  }
}

bool gamma_star_admissible(const Eigen::Matrix3d& gs, const Eigen::Matrix3d& gamma, int d) {
  for (int a = 0; a < d; ++a) {
    Real off = 0;
    for (int b = 0; b < d; ++b)
      if (b != a) off += std::abs(gs(a, b));
    if (!(gs(a, a) > off)) return false;
  }
  const Eigen::Matrix3d sym = 0.5 * (gs + gs.transpose());
  Real lmin = sym(0, 0);
  if (d == 2) {
    const Real m = 0.5 * (sym(0, 0) + sym(1, 1)), q = 0.5 * (sym(0, 0) - sym(1, 1));
    lmin = m - std::sqrt(q * q + sym(0, 1) * sym(0, 1));
  } else if (d == 3) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(sym, Eigen::EigenvaluesOnly);
    lmin = es.eigenvalues().minCoeff();
  }
  return lmin > 0.1 * gamma.topLeftCorner(d, d).trace() / d;
}

Real trace_of_inverse_over_dim(const Eigen::Matrix3d& M, int d) {
  Eigen::Matrix3d inv;
  const Real cond = small_inverse(M, d, inv);
  if (!std::isfinite(cond)) return std::numeric_limits<Real>::infinity();
  return inv.topLeftCorner(d, d).trace() / d;
}

}  // namespace vrsph::spe
