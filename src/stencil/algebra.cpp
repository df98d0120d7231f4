// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
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

namespace {

// One per-row output of the spliced stencil: each row's from the stencil it came from.
template <class T>
void splice_per_row(const std::vector<T>& base, const std::vector<T>& from, std::span<const char> rows,
                    std::vector<T>& out) {
  out.clear();
  if (base.empty() && from.empty()) return;
  out.resize(rows.size(), T{});
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::vector<T>& src = rows[i] ? from : base;
    if (!src.empty()) out[i] = src[i];
  }
}

}  // namespace

void splice_rows(const Stencil& base, const Stencil& from, std::span<const char> rows, Stencil& out) {
  check<InputError>(&out != &base && &out != &from, "splice_rows: the output must be a third stencil");
  check<InputError>(base.kind == from.kind && base.dim == from.dim && base.rows() == from.rows() &&
                        base.components() == from.components(),
                    "splice_rows: a ", to_string(base.kind), " stencil of ", base.rows(), " rows and ", base.components(),
                    " components in ", base.dim, "D cannot take rows of a ", to_string(from.kind), " stencil of ",
                    from.rows(), " rows and ", from.components(), " components in ", from.dim, "D");
  check<InputError>(static_cast<Index>(rows.size()) == base.rows(), "splice_rows: the row mask has ", rows.size(),
                    " entries for ", base.rows(), " rows (size mismatch)");
  const auto n = static_cast<std::size_t>(base.rows());
  const bool with_rhs = !base.rhs.empty() || !from.rhs.empty();
  out.kind = base.kind;
  out.dim = base.dim;
  out.method = base.method;
  out.row_ptr.resize(n + 1);
  out.row_ptr[0] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Stencil& s = rows[i] ? from : base;
    out.row_ptr[i + 1] = out.row_ptr[i] + s.row_end(static_cast<Index>(i)) - s.row_begin(static_cast<Index>(i));
  }
  const auto nnz = static_cast<std::size_t>(out.row_ptr[n]);
  out.col.resize(nnz);
  out.diag.resize(n);
  out.values.resize(static_cast<std::size_t>(base.components()));
  for (auto& v : out.values) v.resize(nnz);
  out.rhs.assign(with_rhs ? nnz : 0, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Stencil& s = rows[i] ? from : base;
    const auto b = static_cast<std::size_t>(s.row_begin(static_cast<Index>(i)));
    const auto e = static_cast<std::size_t>(s.row_end(static_cast<Index>(i)));
    const auto o = static_cast<std::size_t>(out.row_ptr[i]);
    std::copy(s.col.begin() + static_cast<std::ptrdiff_t>(b), s.col.begin() + static_cast<std::ptrdiff_t>(e),
              out.col.begin() + static_cast<std::ptrdiff_t>(o));
    for (std::size_t c = 0; c < out.values.size(); ++c)
      std::copy(s.values[c].begin() + static_cast<std::ptrdiff_t>(b), s.values[c].begin() + static_cast<std::ptrdiff_t>(e),
                out.values[c].begin() + static_cast<std::ptrdiff_t>(o));
    out.diag[i] = static_cast<Index>(o) + s.diag[i] - static_cast<Index>(b);
    if (!with_rhs) continue;
    if (s.rhs.empty()) {
      out.rhs[static_cast<std::size_t>(out.diag[i])] = 1;  // the row approximates the operator at x_i itself
    } else {
      std::copy(s.rhs.begin() + static_cast<std::ptrdiff_t>(b), s.rhs.begin() + static_cast<std::ptrdiff_t>(e),
                out.rhs.begin() + static_cast<std::ptrdiff_t>(o));
    }
  }
  splice_per_row(base.residual, from.residual, rows, out.residual);
  splice_per_row(base.local_failure, from.local_failure, rows, out.local_failure);
  splice_per_row(base.condition, from.condition, rows, out.condition);
  splice_per_row(base.xi, from.xi, rows, out.xi);
  splice_per_row(base.wall_flux, from.wall_flux, rows, out.wall_flux);
  splice_per_row(base.negative_volumes, from.negative_volumes, rows, out.negative_volumes);
}

}  // namespace vrsph
