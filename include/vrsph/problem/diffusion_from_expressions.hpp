// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A time-dependent diffusion problem on any cloud from expressions (muParser syntax; u, s,
// g, q may use t): the manufactured-solution convention of from_expressions.hpp in time.
// With an exact u(x, t): s defaults to ∂u/∂t - div(a grad u) (div(M grad u) with a
// mobility), g to u, q to n·a grad u (n·M grad u), u0 to u(x, 0); the derivatives of
// expressions are finite differences (4th order in t and x, relative error ~1e-9).
#include <string>
#include <vector>
#include <vrsph/problem/diffusion.hpp>

namespace vrsph {

struct DiffusionExpressions {
  std::string u;                      ///< exact solution u(x, y, z, t) (optional)
  std::string a;                      ///< coefficient a(x, y, z) > 0 (default 1; constant in time)
  std::vector<std::string> mobility;  ///< or a diagonal mobility, one expression per direction
  std::string s, g, q, u0;            ///< source, Dirichlet and Neumann data (x, y, z, t), initial values (x, y, z)
};

/// Throws ConfigError naming a missing expression (without u: s, u0 and the data of every
/// tagged boundary are required) or a conflict, InputError for an expression that does not
/// parse or a coefficient that is not positive and finite at a particle.
DiffusionProblem diffusion_from_expressions(PointCloud cloud, const DiffusionExpressions& e);

}  // namespace vrsph
