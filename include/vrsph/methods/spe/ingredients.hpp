// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Per-particle ingredients of the [SPE] schemes (METHODS §3.7): the four
// kernel-gradient options G1–G4 (15)–(18), the Shepard sum ν (13), the correction matrix
// A and corrected gradient g* = A^-T g (23)–(25), the vectors N (53) and Ñ (65), the
// tensors Γ (55) and Γ* (70)–(71), and the monotonicity diagnostic ξ = Cᵀ Ñ (94).
//
// Conventions (METHODS §1.1, §3.7): Δ_J = x_J - x_I, r = |Δ_J|, g⁰_IJ = ∇_{x_I} W(|x_I - x_J|)
// = -W'(r) Δ_J / r points from I to J. One row at a time, so the schemes and the tests
// share exactly the same arithmetic.
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph::spe {

enum class GradientOption { G1, G2, G3, G4 };
/// "g1".."g4"; throws ConfigError otherwise.
GradientOption parse_gradient_option(const std::string& name);

/// What one row I sees: its neighbours J (self excluded) and the kernel of each pair with
/// the symmetrised smoothing length h̃_IJ (26).
struct RowGeometry {
  int dim = 2;
  std::vector<Vec3> delta;      ///< Δ_J = x_J - x_I
  std::vector<Real> r;          ///< |Δ_J|
  std::vector<Real> volume;     ///< V_J
  std::vector<Real> W;          ///< W(r; h̃_IJ)
  std::vector<Real> dW_over_r;  ///< W'(r; h̃_IJ)/r (<= 0)
  Real volume_self = 0;         ///< V_I
  Real W_self = 0;              ///< W(0; h_I), for ν_I (13)
  void resize(std::size_t n) {
    delta.resize(n);
    r.resize(n);
    volume.resize(n);
    W.resize(n);
    dW_over_r.resize(n);
  }
  std::size_t size() const { return delta.size(); }
};

struct RowIngredients {
  std::vector<Vec3> g;      ///< the chosen kernel gradient g_IJ
  std::vector<Vec3> gstar;  ///< C g_IJ (corrected, (23))
  std::vector<Real> radial; ///< Δ_J·g_IJ / r² (the Brookshaw factor; >= 0 for radial options)
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), C = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d Gamma = Eigen::Matrix3d::Zero(), GammaStar = Eigen::Matrix3d::Zero();
  Vec3 N = Vec3::Zero(), Ntilde = Vec3::Zero(), xi = Vec3::Zero();
  Real nu = 0;
  /// Condition number of A (equilibrated); +inf when A is singular (then g*, C, ξ are zero).
  Real condition = 0;
};

/// Fills `out` for one row; the d×d blocks live in the top-left corner of the 3×3 matrices.
void compute_ingredients(const RowGeometry& row, GradientOption option, RowIngredients& out);

/// The M-SPH bracket T̄_IJ = V_J [Δ·g/r² - Ñ·g*] ((90), unit mobility) and Γ* = Σ T̄ ΔΔᵀ.
void monotone_transmissibilities(const RowGeometry& row, const RowIngredients& in, std::vector<Real>& T,
                                 Eigen::Matrix3d& gamma_star);

/// METHODS §3.7.5 admissibility of Γ*: strictly diagonally dominant with positive diagonal
/// (Lemma 2) and λ_min(Γ*) > 0.1 tr(Γ)/d. The paper's "Γ* = 0" test (R7) is garbled.
bool gamma_star_admissible(const Eigen::Matrix3d& gamma_star, const Eigen::Matrix3d& gamma, int dim);

/// tr(M^-1)/d of the top-left d×d block; +inf when it is singular.
Real trace_of_inverse_over_dim(const Eigen::Matrix3d& M, int dim);

}  // namespace vrsph::spe
