#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/spe/ingredients.hpp>
#include <vrsph/methods/taylor/local_system.hpp>

namespace vrsph::spe {

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
  taylor::SmallMatrix Ad = out.A.topLeftCorner(d, d), Ainv;
  out.condition = taylor::equilibrated_inverse(Ad, Ainv);
  out.C.setZero();
  if (std::isfinite(out.condition)) out.C.topLeftCorner(d, d) = Ainv.transpose();
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
  const Eigen::MatrixXd sym = 0.5 * (gs.topLeftCorner(d, d) + gs.topLeftCorner(d, d).transpose());
  const Real lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
  return lmin > 0.1 * gamma.topLeftCorner(d, d).trace() / d;
}

Real trace_of_inverse_over_dim(const Eigen::Matrix3d& M, int d) {
  taylor::SmallMatrix Md = M.topLeftCorner(d, d), inv;
  const Real cond = taylor::equilibrated_inverse(Md, inv);
  if (!std::isfinite(cond)) return std::numeric_limits<Real>::infinity();
  return inv.trace() / d;
}

}  // namespace vrsph::spe
