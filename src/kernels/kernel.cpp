// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/kernel.hpp>
#include "../core/quadrature.hpp"

namespace vrsph {

const std::vector<KernelInfo>& kernel_catalogue() {
  static const std::vector<KernelInfo> list = {
      {KernelType::CubicSpline, "cubic", "cubic B-spline, support-radius form [QW](2.4)", 2.0},
      {KernelType::CubicSplineSPE, "cubic-spe", "cubic B-spline, smoothing-length form [SPE](12), support 2l", 2.0},
      {KernelType::Gaussian, "gaussian", "Gaussian of [AAR], width l, truncated at 6l", 6.0},
      {KernelType::Quintic, "quintic", "quintic spline, support 3l", 3.0},
      {KernelType::WendlandC2, "wendland-c2", "Wendland C2, support 2l", 2.0},
      {KernelType::WendlandC4, "wendland-c4", "Wendland C4, support 2l", 2.0},
  };
  return list;
}

const KernelInfo& kernel_info(KernelType type) {
  for (const auto& k : kernel_catalogue())
    if (k.type == type) return k;
  throw ConfigError("unknown kernel type");
}

KernelType parse_kernel(std::string_view name) {
  std::string known;
  for (const auto& k : kernel_catalogue()) {
    if (k.name == name) return k.type;
    known += (known.empty() ? "" : ", ") + std::string(k.name);
  }
  throw ConfigError("unknown kernel '" + std::string(name) + "' (known: " + known + ")");
}

namespace detail {

namespace {
Real integrate_normalisation(KernelType type, int dim) {
  // 12 equal panels put panel edges at every breakpoint (1/3, 1/2, 2/3); 20 points
  // per panel integrate the polynomial pieces exactly and the Gaussian to round-off.
  static const detail::QuadratureRule gl = detail::gauss_legendre(20);
  constexpr int panels = 12;
  Real integral = 0;
  for (int p = 0; p < panels; ++p) {
    const Real a = Real(p) / panels, b = Real(p + 1) / panels;
    for (std::size_t k = 0; k < gl.x.size(); ++k) {
      const Real R = 0.5 * (a + b) + 0.5 * (b - a) * gl.x[k];
      integral += 0.5 * (b - a) * gl.w[k] * std::pow(R, dim - 1) * kernel_profile(type, dim, R).w;
    }
  }
  const Real sphere = dim == 1 ? 2.0 : dim == 2 ? 2 * std::numbers::pi : 4 * std::numbers::pi;
  return 1.0 / (sphere * integral);
}
}  // namespace

Real kernel_normalisation(KernelType type, int dim) {
  // Computed once per (kernel, dimension): Kernel objects are created per particle.
  static const auto table = [] {
    std::array<std::array<Real, 3>, 6> t{};
    for (const auto& k : kernel_catalogue())
      for (int d = 1; d <= 3; ++d)
        t[static_cast<std::size_t>(k.type)][static_cast<std::size_t>(d - 1)] = integrate_normalisation(k.type, d);
    return t;
  }();
  return table[static_cast<std::size_t>(type)][static_cast<std::size_t>(dim - 1)];
}

}  // namespace detail

Kernel::Kernel(KernelType type, int dim, Real support_radius) : type_(type), dim_(dim), h_(support_radius) {
  check<InputError>(dim >= 1 && dim <= 3, "kernel dimension must be 1, 2 or 3, got ", dim);
  check<InputError>(std::isfinite(support_radius) && support_radius > 0,
                    "kernel support radius h must be positive and finite, got h = ", support_radius);
  sigma_ = detail::kernel_normalisation(type, dim);
  inv_h_d_ = std::pow(h_, -dim);
  ratio_scale_ = sigma_ * inv_h_d_ / (h_ * h_);
}

Kernel Kernel::from_smoothing_length(KernelType type, int dim, Real smoothing_length) {
  check<InputError>(std::isfinite(smoothing_length) && smoothing_length > 0,
                    "smoothing length must be positive and finite, got ", smoothing_length);
  return Kernel(type, dim, kernel_info(type).support_per_smoothing_length * smoothing_length);
}

Real Kernel::W_profile(Real r) const { return sigma_ * inv_h_d_ * detail::kernel_profile(type_, dim_, r / h_).w; }
Real Kernel::dW(Real r) const { return sigma_ * inv_h_d_ / h_ * detail::kernel_profile(type_, dim_, r / h_).dw; }
Real Kernel::d2W(Real r) const {
  return sigma_ * inv_h_d_ / (h_ * h_) * detail::kernel_profile(type_, dim_, r / h_).d2w;
}
void Kernel::dW_over_r(const Real* r, Real* out, int n) const {
  const Real inv_h = 1 / h_, scale = sigma_ * inv_h_d_ * inv_h * inv_h;  // as the scalar form's sigma h^-d / h^2
  if (type_ != KernelType::CubicSpline) {
    for (int k = 0; k < n; ++k) out[k] = dW_over_r(r[k]);
    return;
  }
  // [QW](2.4): w'(R)/R = -12 + 18 R (R < 1/2), -6 (1 - R)^2 / R (R < 1), 0 beyond.
  // Both branches evaluated and selected (vectorises; the distances are in no order, so
  // the branches mispredicted). R > 0 for neighbours (coincident points are rejected), and
  // the unused quotient of a selected-away branch is discarded.
  for (int k = 0; k < n; ++k) {
    // R = r / h as the scalar form computes it: at r = h a product with 1/h can round to just
    // below 1 and give a round-off weight where the scalar form (the stencils') gives 0.
    const Real R = r[k] / h_;
    const Real s = 1 - R;
    const Real inner = -12 + 18 * R;
    const Real outer = -6 * s * s / (R > 0 ? R : 1);
    const Real ratio = R < 0.5 ? inner : R < 1 ? outer : 0.0;
    out[k] = scale * ratio;
  }
}

Real Kernel::dW_over_r_profile(Real r) const {
  const Real R = r / h_;
  const auto p = detail::kernel_profile(type_, dim_, R);
  // All profiles have w'(0) = 0, so w'(R)/R -> w''(0) as R -> 0.
  const Real ratio = R > 1e-8 ? p.dw / R : p.d2w;
  return ratio_scale_ * ratio;
}

}  // namespace vrsph
