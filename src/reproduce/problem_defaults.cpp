// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/reproduce/problem_defaults.hpp>

namespace vrsph {

ProblemDefaults problem_defaults(const std::string& problem) {
  ProblemDefaults d;
  if (problem == "aar-derivative" || problem == "aar-static") {
    d.dim = 1;
    d.kernel = KernelType::Gaussian;
    d.h_factor = 6;  // Gaussian with l = dx, truncated at 6 l
    d.delta = 0.25;
    d.ghosts = false;
  }
  if (problem == "spe-dirichlet" || problem == "spe-mixed" || problem == "spe-channel" || problem == "spe-lognormal" ||
      problem == "spe10") {
    d.kernel = KernelType::CubicSplineSPE;
    d.h_factor = 1.001;
    d.delta = 0.1001;
    d.cell_layout = true;
    d.support_per_h_factor = 2;
    d.ghosts = false;
  }
  return d;
}

}  // namespace vrsph
