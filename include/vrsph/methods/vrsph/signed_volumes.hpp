// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Exact moment weights for a row whose moment conditions no non-negative volumes meet
// (VRSPH option boundary=signed, beyond [QW]; docs/methods.md "Feasibility everywhere").
//
// Next to a wall the third moments of a Laplacian row cannot vanish with v >= 0 when the
// particle is closer to the wall than to its nearest inner neighbour: in the normal
// direction Σ w d = 0 and Σ w d^3 = 0 need a neighbour inside at least as close as the wall,
// and neither a larger support nor extra points on the wall supply one. Such a row keeps
// second order only with some negative volumes; this picks few and small ones:
//   min ||Ã(p - q) - b̃||² + μ² ||q||²,  p, q >= 0  (an NNLS on [Ã -Ã; 0 μI]),
// Ã the row- and column-equilibrated moment matrix, v = p - q; then the residual left by the
// penalty is removed by a minimum-norm correction on the support found. The row then no
// longer has the sign structure of an M-matrix (the count is reported).
#include <vector>
#include <vrsph/methods/vrsph/nnls.hpp>

namespace vrsph {

struct SignedVolumesResult {
  Real residual = 0;  ///< ||A v - b||_2 of the original system
  int negative = 0;   ///< number of v_j < 0
};

class SignedVolumeSolver {
 public:
  /// A: m x n row-major (the layout NnlsSolver works on), b: m; v receives n values.
  SignedVolumesResult solve(const Real* A, int m, int n, const Real* b, Real* v);

 private:
  NnlsSolver nnls_{64, 512};
  std::vector<Real> M_, c_, z_, row_scale_, col_scale_, At_;
  std::vector<char> dead_;  // columns of round-off size (a neighbour on the support's edge): left out
};

}  // namespace vrsph
