// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The reference weight functions of [IM] (METHODS §2.6–2.7):
// radial weights w on [0, 1) (zero beyond), normalised so that ∫_{R^d} w(|x|) dx = 1 in the
// dimension they are made for, with w_h(r) = h^-d w(r/h).
//
//   pi1, pi2, pi3           interpolants (pi2: the cubic B-spline of §2.1; pi3 with the
//                           constant 6/π of the S1 erratum, the printed 5/π integrates to 5/6)
//   grad1, grad2, grad3     gradient weights (grad2 = -(1/d) r pi2'(r): SPH's gradient)
//   delta1, delta2, delta3  Laplacian weights (delta2 = grad2: SPH's Brookshaw Laplacian)
//
// and the construction of App. C as corrected in METHODS §2.7: w = γ r^q (1 + Σ_{ℓ=1..p} a_ℓ r^ℓ)
// with q = 0 (interpolant), 1 (gradient), 2 (Laplacian), p = 1 + ⌊n/2⌋, continuity at r = 1
// and the vanishing radial moments ∫ r^{d-1+2j} w = 0, j = 1..⌊n/2⌋ (Hypothesis 1 of order n);
// pi1/grad1/delta1 (n = 1) and pi3/grad3/delta3 (n = 3) are its solutions in 2D. METHODS §2.6
// only changes the constant in other dimensions; that would cost pi3/grad3/delta3 their
// vanishing second moment in 1D and 3D, so there they are App. C's n = 3 weights of that
// dimension (identical in 2D).
// A weight is stored as polynomial pieces in r, so values, derivatives and moments are exact.
#include <string>
#include <vector>
#include <vrsph/core/types.hpp>

namespace vrsph {

enum class WeightOperator { Interpolant, Gradient, Laplacian };

class ReferenceWeight {
 public:
  /// A polynomial Σ_k c_k r^k on [from, to).
  struct Piece {
    Real from = 0, to = 1;
    std::vector<Real> c;
  };
  ReferenceWeight(std::string name, int dim, std::vector<Piece> pieces);

  const std::string& name() const { return name_; }
  int dim() const { return dim_; }
  const std::vector<Piece>& pieces() const { return pieces_; }
  /// w(r) for r >= 0 (0 for r >= 1); w'(r).
  Real value(Real r) const;
  Real derivative(Real r) const;
  /// w_h(r) = h^-d w(r/h).
  Real value(Real r, Real h) const;
  /// ∫_0^1 r^(d-1+m) w(r) dr, exact. |S^(d-1)| times the m = 0 moment is the integral of w over R^d.
  Real radial_moment(int m) const;
  /// The largest odd n <= 15 for which Hypothesis 1 holds: ∫ r^(d-1+2j) w = 0 (relative to
  /// the j-th moment of |w|, to 1e-12) for j = 1..⌊n/2⌋. Every normalised weight has n >= 1.
  int hypothesis1_order() const;
  /// k of Hypothesis 2 by Prop. 1 of [IM]: the lowest power of r near 0 minus 1 (-1: none).
  int hypothesis2_order() const;

 private:
  std::string name_;
  int dim_;
  std::vector<Piece> pieces_;
};

/// |S^(d-1)|: 2, 2π, 4π.
Real unit_sphere_area(int dim);

/// pi1..pi3, grad1..grad3, delta1..delta3 normalised in dimension dim (1..3). ConfigError otherwise.
ReferenceWeight reference_weight(const std::string& name, int dim);
std::vector<std::string> reference_weight_names();
/// The operator a named weight is made for: pi* interpolant, grad* gradient, delta* Laplacian.
/// ConfigError for any other name.
WeightOperator reference_weight_operator(const std::string& name);

/// App. C (METHODS §2.7): the polynomial weight for `op` in dimension dim with Hypothesis 1 of
/// odd order n (1 <= n <= 15) and Hypothesis 2 of order q - 1; smooth_end adds w'(1) = 0
/// (one more coefficient). ConfigError for bad settings, NumericalError for a singular system.
ReferenceWeight construct_reference_weight(int dim, WeightOperator op, int n, bool smooth_end = false);

}  // namespace vrsph
