// SPDX-License-Identifier: BSD-3-Clause
// Radial profiles of every kernel on the unit support R = r/h in [0,1).
// Derivatives are with respect to R. One small function per kernel.
#include <cmath>
#include <vrsph/kernels/kernel.hpp>

namespace vrsph::detail {

namespace {
using P = Profile;

P cubic_qw(Real R) {  // [QW](2.4)
  if (R < 0.5) return {1 - 6 * R * R + 6 * R * R * R, -12 * R + 18 * R * R, -12 + 36 * R};
  const Real s = 1 - R;
  return {2 * s * s * s, -6 * s * s, 12 * s};
}

P cubic_spe(Real R) {  // [SPE](12) in z = r/l = 2R, support 2l
  const Real z = 2 * R;
  if (z <= 1) return {1 - 1.5 * z * z + 0.75 * z * z * z, 2 * (-3 * z + 2.25 * z * z), 4 * (-3 + 4.5 * z)};
  const Real s = 2 - z;
  return {0.25 * s * s * s, 2 * (-0.75 * s * s), 4 * (1.5 * s)};
}

P gaussian(Real R) {  // q = r/l = 6R, truncated at q = 6
  const Real q = 6 * R, e = std::exp(-q * q);
  return {e, 6 * (-2 * q * e), 36 * (4 * q * q - 2) * e};
}

P quintic(Real R) {  // q = r/l = 3R, support 3l
  const Real q = 3 * R;
  Real w = 0, dw = 0, d2w = 0;
  const Real a[3] = {3 - q, 2 - q, 1 - q};
  const Real c[3] = {1, -6, 15};
  for (int k = 0; k < 3; ++k) {
    if (a[k] <= 0) continue;
    const Real s = a[k], s2 = s * s;
    w += c[k] * s2 * s2 * s;
    dw += c[k] * -5 * s2 * s2;
    d2w += c[k] * 20 * s2 * s;
  }
  return {w, 3 * dw, 9 * d2w};
}

P wendland_c2(Real R, int dim) {
  const Real s = 1 - R;
  if (dim == 1) return {s * s * s * (3 * R + 1), -12 * R * s * s, 12 * s * (3 * R - 1)};
  return {s * s * s * s * (4 * R + 1), -20 * R * s * s * s, 20 * s * s * (4 * R - 1)};
}

P wendland_c4(Real R, int dim) {
  const Real s = 1 - R, s2 = s * s, s3 = s2 * s;
  if (dim == 1) return {s3 * s2 * (8 * R * R + 5 * R + 1), -14 * R * s2 * s2 * (4 * R + 1), -14 * s3 * (1 + 3 * R - 24 * R * R)};
  return {s3 * s3 * (35 * R * R + 18 * R + 3), -56 * R * s3 * s2 * (5 * R + 1), -56 * s2 * s2 * (1 + 4 * R - 35 * R * R)};
}
}  // namespace

Profile kernel_profile(KernelType type, int dim, Real R) {
  if (R >= 1) return {0, 0, 0};
  switch (type) {
    case KernelType::CubicSpline: return cubic_qw(R);
    case KernelType::CubicSplineSPE: return cubic_spe(R);
    case KernelType::Gaussian: return gaussian(R);
    case KernelType::Quintic: return quintic(R);
    case KernelType::WendlandC2: return wendland_c2(R, dim);
    case KernelType::WendlandC4: return wendland_c4(R, dim);
  }
  return {0, 0, 0};
}

}  // namespace vrsph::detail
