// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/core/error.hpp>
#include <vrsph/stencil/algebra.hpp>

namespace vrsph {

Stencil stencil_from_matrix(const SparseMatrix& m, OperatorKind kind, int dim, std::string method) {
  check<InputError>(m.rows() == m.cols(), "stencil_from_matrix: matrix must be square");
  Stencil s;
  s.kind = kind;
  s.dim = dim;
  s.method = std::move(method);
  const Index n = static_cast<Index>(m.rows());
  s.row_ptr.assign(static_cast<std::size_t>(n) + 1, 0);
  s.diag.assign(static_cast<std::size_t>(n), 0);
  s.values.assign(1, {});
  auto& v = s.values[0];
  s.col.reserve(static_cast<std::size_t>(m.nonZeros() + n));
  v.reserve(static_cast<std::size_t>(m.nonZeros() + n));
  for (Index i = 0; i < n; ++i) {
    bool diag_done = false;
    for (SparseMatrix::InnerIterator it(m, i); it; ++it) {  // columns ascending in a compressed matrix
      const auto j = static_cast<Index>(it.col());
      if (!diag_done && j >= i) {
        s.diag[static_cast<std::size_t>(i)] = static_cast<Index>(s.col.size());
        diag_done = true;
        if (j > i) {
          s.col.push_back(i);
          v.push_back(0);
        }
      }
      s.col.push_back(j);
      v.push_back(it.value());
    }
    if (!diag_done) {
      s.diag[static_cast<std::size_t>(i)] = static_cast<Index>(s.col.size());
      s.col.push_back(i);
      v.push_back(0);
    }
    s.row_ptr[static_cast<std::size_t>(i) + 1] = static_cast<Index>(s.col.size());
  }
  return s;
}

Stencil nested_second_derivative(const Stencil& g, const Field* c, std::span<const char> rows, OperatorKind kind) {
  check<InputError>(g.kind == OperatorKind::Gradient, "nested second derivative needs a gradient stencil");
  check<InputError>(static_cast<Index>(rows.size()) == g.rows(), "nested second derivative: row mask size mismatch");
  check<InputError>(c == nullptr || c->size() == g.rows(), "nested second derivative: coefficient size mismatch");
  const Index n = g.rows();
  SparseMatrix sum(n, n);
  for (int a = 0; a < g.components(); ++a) {
    const SparseView ga = as_eigen(g, a);
    SparseMatrix term = c ? SparseMatrix(c->asDiagonal() * ga) : SparseMatrix(ga);  // diag(c) D_a
    term = SparseMatrix(ga * term);  // D_a (c D_a)
    sum = a == 0 ? term : SparseMatrix(sum + term);
  }
  // Empty the rows that were not asked for (their inner derivatives may be incomplete).
  for (Index i = 0; i < n; ++i)
    if (!rows[static_cast<std::size_t>(i)])
      for (SparseMatrix::InnerIterator it(sum, i); it; ++it) it.valueRef() = 0;
  sum.prune(0.0);
  sum.makeCompressed();
  Stencil s = stencil_from_matrix(sum, kind, g.dim, g.method);
  return s;
}

}  // namespace vrsph
