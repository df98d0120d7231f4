// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A boundary value problem on any cloud from expressions in x, y, z (muParser syntax or
// catalogue names, see analysis/functions.hpp), as the CLI's `solve --cloud-file` takes
// them. Defaults follow the manufactured-solution convention: with an exact u, f
// defaults to div(a grad u), g to u and q to a grad(u).n; without u, f, g (when the
// cloud has Dirichlet particles) and q (when it has Neumann particles) are required.
#include <string>
#include <vector>
#include <vrsph/problem/boundary_value_problem.hpp>

namespace vrsph {

struct ProblemExpressions {
  std::string u;  ///< exact solution (optional)
  std::string a;  ///< coefficient (default 1)
  std::string f, g, q;
  /// Diagonal mobility m_1..m_d instead of a (one expression per direction): f defaults to
  /// div(M grad u) and q to n·M grad u.
  std::vector<std::string> mobility = {};
  /// The length finite differences of the expressions step by (ScalarFunction::length_scale);
  /// 0: length_scale of the cloud. A caller holding one rank's part gives the whole cloud's.
  Real length_scale = 0;
};

/// Per-particle values given directly (e.g. columns of the cloud file, `--f-column`); each
/// replaces the expression of the same role, which must then be empty. Derived defaults
/// need formulas: with u or a given as values, f = div(a grad u) cannot be derived (give f),
/// nor, with u as values, q = a du/dn (give q).
struct ProblemValues {
  const Field* u = nullptr;
  const Field* a = nullptr;
  const Field* f = nullptr;
  const Field* g = nullptr;
  const Field* q = nullptr;
};

struct ExpressionProblem {
  BoundaryValueProblem problem;
  Field exact;  ///< u at every particle; empty without u
};

/// Throws ConfigError naming the missing expression, InputError for an expression that
/// does not parse or is not finite at a particle (naming its role and the particle).
ExpressionProblem problem_from_expressions(PointCloud cloud, const ProblemExpressions& e, const ProblemValues& values = {});

}  // namespace vrsph
