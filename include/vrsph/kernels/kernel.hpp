// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Radial smoothing kernels W(r) with compact support radius h: W(r) = 0 for r >= h.
//
// Convention (METHODS.md §1.3, X1): every kernel is stored with its *support radius*
// h. Papers that use a smoothing length l ([SPE], [AAR]) convert once with
// Kernel::from_smoothing_length (support = ratio * l, e.g. 2l for the cubic spline).
// W is normalised so that its integral over R^d is 1 (d = 1, 2, 3); the constant is
// computed by exact Gauss–Legendre quadrature of the radial profile and is checked
// against the published constants in the tests.
//
// Units: r and h are lengths; W has units length^-d, W' length^-d-1, W'' length^-d-2.
// W'(r) <= 0 for every kernel here (decay condition).
#include <string>
#include <string_view>
#include <vrsph/core/types.hpp>

namespace vrsph {

enum class KernelType {
  CubicSpline,     ///< [QW](2.4): 1-6R^2+6R^3 (R<1/2), 2(1-R)^3 (R<1), R = r/h
  CubicSplineSPE,  ///< [SPE](12): same function written in z = r/l, support 2l (Xi_1 = 2/3, erratum R1)
  Gaussian,        ///< [AAR]: exp(-(r/l)^2)/(pi^{d/2} l^d), truncated at 6l (METHODS §2.3)
  Quintic,         ///< quintic spline, support 3l (METHODS §2.4)
  WendlandC2,      ///< Wendland C2, support 2l
  WendlandC4,      ///< Wendland C4, support 2l
};

struct KernelInfo {
  KernelType type;
  std::string_view name;            ///< CLI name
  std::string_view description;
  Real support_per_smoothing_length;  ///< support radius / smoothing length
};

const std::vector<KernelInfo>& kernel_catalogue();
const KernelInfo& kernel_info(KernelType type);
/// Throws ConfigError listing the known names.
KernelType parse_kernel(std::string_view name);

class Kernel {
 public:
  /// Throws InputError if dim is not 1..3 or the support radius is not positive and finite.
  Kernel(KernelType type, int dim, Real support_radius);
  static Kernel from_smoothing_length(KernelType type, int dim, Real smoothing_length);

  KernelType type() const { return type_; }
  int dim() const { return dim_; }
  Real support() const { return h_; }
  /// sigma_d in W(r) = sigma_d h^-d w(r/h), w the unnormalised profile with w(0) = 1 (cubic) etc.
  Real normalisation() const { return sigma_; }

  Real W(Real r) const {
    if (type_ != KernelType::CubicSpline) return W_profile(r);
    // The cubic spline inline (the weights of the rows exact on polynomials, per neighbour), the
    // same arithmetic as its profile's: [QW](2.4) w(R) = 1 - 6 R^2 + 6 R^3 (R < 1/2), 2 (1 - R)^3 (R < 1).
    const Real R = r / h_;
    Real w = 0;
    if (R < 0.5) w = 1 - 6 * R * R + 6 * R * R * R;
    else if (R < 1) w = 2 * (1 - R) * (1 - R) * (1 - R);
    return sigma_ * inv_h_d_ * w;
  }
  Real dW(Real r) const;   ///< dW/dr
  Real d2W(Real r) const;  ///< d^2W/dr^2
  /// W'(r)/r, with its finite limit W''(0) at r = 0. This is [QW]'s -Y/2 = F_ij.
  Real dW_over_r(Real r) const {
    if (type_ != KernelType::CubicSpline) return dW_over_r_profile(r);
    // The cubic spline inline (every stencil builder's inner loop), the same arithmetic as its
    // profile's: [QW](2.4) w'(R) = -12 R + 18 R^2 (R < 1/2), -6 (1 - R)^2 (R < 1), w''(0) = -12.
    const Real R = r / h_;
    Real ratio = 0;
    if (R < 0.5) ratio = R > 1e-8 ? (-12 * R + 18 * R * R) / R : -12 + 36 * R;
    else if (R < 1) ratio = -6 * (1 - R) * (1 - R) / R;
    return ratio_scale_ * ratio;
  }
  /// out[k] = W'(r[k])/r[k] for k < n: the per-neighbour loop of the stencil builders,
  /// with the kernel type dispatched once (the cubic spline inline) instead of per call.
  void dW_over_r(const Real* r, Real* out, int n) const;

 private:
  KernelType type_;
  int dim_;
  Real h_;
  Real sigma_;
  Real inv_h_d_;  // h^-d
  Real ratio_scale_;  // sigma h^-d / h^2: W'/r = ratio_scale_ w'(R)/R
  Real dW_over_r_profile(Real r) const;
  Real W_profile(Real r) const;
};

namespace detail {
/// Unnormalised radial profile w(R), w'(R), w''(R) on R = r/h in [0,1) (0 beyond).
struct Profile {
  Real w, dw, d2w;
};
Profile kernel_profile(KernelType type, int dim, Real R);
/// 1 / (|S^{d-1}| * int_0^1 R^{d-1} w(R) dR)
Real kernel_normalisation(KernelType type, int dim);
}  // namespace detail

}  // namespace vrsph
