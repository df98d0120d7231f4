// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Defaults that belong to a built-in problem rather than to the command line: the [AAR]
// problems are one-dimensional, use the Gaussian kernel with smoothing length dx
// (support 6 dx, METHODS §2.3) and perturb by U(-dx/4, dx/4) (METHODS §5.2); the [QW]
// problems use the cubic spline with h = 3 dx and U(-dx/2, dx/2); the [SPE] problems use its
// smoothing-length form with f = 1.001 (support 2f dx), layout B and U(-0.1001 dx, 0.1001 dx)
// (METHODS §5.3, R14). Options the user gives
// explicitly always win.
#include <string>
#include <vrsph/kernels/kernel.hpp>

namespace vrsph {

struct ProblemDefaults {
  int dim = 2;
  KernelType kernel = KernelType::CubicSpline;
  Real h_factor = 3;  ///< support radius / dx
  Real delta = 0.5;   ///< perturbation amplitude / dx
  bool ghosts = true; ///< operator studies: ghost layer outside the domain
  bool cell_layout = false;         ///< layout B (cell centres + boundary particles) instead of A
  /// The support radius is support_per_h_factor x h_factor x dx: 2 for the [SPE] problems,
  /// whose --h-factor is the paper's f = l/dx with support 2l (METHODS §1.3).
  Real support_per_h_factor = 1;
};

/// Known for every built-in operator and BVP problem; a generic default otherwise.
ProblemDefaults problem_defaults(const std::string& problem);

}  // namespace vrsph
