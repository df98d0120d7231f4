// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/uninitialized.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

Stencil make_stencil_pattern(const NeighbourList& nl, OperatorKind kind, int dim, std::string method) {
  Stencil s;
  fill_stencil_pattern(nl, kind, dim, std::move(method), s);
  return s;
}

void reset_stencil(Stencil& s, OperatorKind kind, int dim, std::string method) {
  Stencil kept;
  kept.kind = kind;
  kept.dim = dim;
  kept.method = std::move(method);
  kept.row_ptr = std::move(s.row_ptr);
  kept.col = std::move(s.col);
  kept.diag = std::move(s.diag);
  kept.values = std::move(s.values);
  s = std::move(kept);
}

void fill_stencil_pattern(const NeighbourList& nl, OperatorKind kind, int dim, std::string method, Stencil& s,
                          bool zero_values) {
  reset_stencil(s, kind, dim, std::move(method));
  const Index n = nl.size();
  check<ConfigError>(kind != OperatorKind::Dy || dim >= 2, "operator dy needs dimension >= 2");
  check<ConfigError>(kind != OperatorKind::Dz || dim >= 3, "operator dz needs dimension 3");
  s.row_ptr.resize(static_cast<std::size_t>(n) + 1);
  s.diag.resize(static_cast<std::size_t>(n));
  s.row_ptr[0] = 0;
  // One slot per pair plus the diagonal (lists with self are refused below). Index is 32-bit:
  // a pattern whose size it cannot count is refused by its true size, not wrapped around.
  const long long slots = static_cast<long long>(nl.total()) + n;
  check<ResourceError>(slots <= std::numeric_limits<Index>::max(), "the ", to_string(kind), " stencil would have ", slots,
                       " entries (", nl.total(), " neighbour pairs and ", n, " diagonals), more than the ",
                       std::numeric_limits<Index>::max(), " a 32-bit index can number: reduce the number of particles or "
                       "the smoothing radius (--n, --h-factor)");
  for (Index i = 0; i < n; ++i) s.row_ptr[static_cast<std::size_t>(i) + 1] = s.row_ptr[static_cast<std::size_t>(i)] + nl.count(i) + 1;
  // Column indices plus one value array per component: refused up front if too large.
  const auto ncomp = static_cast<std::size_t>(components(kind, dim));
  check_memory_estimate(static_cast<double>(s.nnz()) * static_cast<double>(sizeof(Index) + ncomp * sizeof(Real)),
                        detail::concat("the ", to_string(kind), " stencil (", s.nnz(), " nonzeros)"),
                        "reduce the number of particles or the smoothing radius (--n, --h-factor)");
  reserve_for_overwrite(s.col, static_cast<std::size_t>(s.nnz()));
  s.col.resize(static_cast<std::size_t>(s.nnz()));
  // Rows in parallel: each writes its own slots.
  bool self_listed = false;
#pragma omp parallel for schedule(static) reduction(|| : self_listed)
  for (Index i = 0; i < n; ++i) {
    const auto row = nl.of(i);
    const auto split = std::lower_bound(row.begin(), row.end(), i);
    if (split != row.end() && *split == i) {
      self_listed = true;
      continue;
    }
    auto out = s.col.begin() + s.row_begin(i);
    out = std::copy(row.begin(), split, out);
    s.diag[static_cast<std::size_t>(i)] = static_cast<Index>(out - s.col.begin());
    *out++ = i;
    std::copy(split, row.end(), out);
  }
  check<ConfigError>(!self_listed, "stencil patterns need neighbour lists without self (search with include_self = false)");
  s.values.resize(static_cast<std::size_t>(components(kind, dim)));
  for (auto& v : s.values) {
    reserve_for_overwrite(v, s.col.size());
    if (zero_values) v.assign(s.col.size(), 0.0);
    else v.resize(s.col.size());  // every entry is written by the caller
  }
}

void set_difference_diagonal(Stencil& s) {
  for (auto& v : s.values)
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < s.rows(); ++i) {
      Real sum = 0;
      const Index d = s.diag[static_cast<std::size_t>(i)];
      for (Index k = s.row_begin(i); k < s.row_end(i); ++k)
        if (k != d) sum += v[static_cast<std::size_t>(k)];
      v[static_cast<std::size_t>(d)] = -sum;
    }
}

Eigen::MatrixXd apply(const Stencil& s, const Field& u) {
  check<InputError>(u.size() == s.rows(), "apply: field has ", u.size(), " values but the stencil has ", s.rows(),
                    " rows (size mismatch)");
  Eigen::MatrixXd out(s.rows(), s.components());
  for (int c = 0; c < s.components(); ++c) out.col(c) = apply_component(s, u, c);
  return out;
}

Field apply_component(const Stencil& s, const Field& u, int component) {
  check<InputError>(u.size() == s.rows(), "apply: field has ", u.size(), " values but the stencil has ", s.rows(),
                    " rows (size mismatch)");
  check<InputError>(component >= 0 && component < s.components(), "apply: component ", component,
                    " out of range for a stencil with ", s.components(), " components");
  Field out(s.rows());
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < s.rows(); ++i) out[i] = row_product(s, component, i, u.data());
  return out;
}

Field average_rhs(const Stencil& s, const Field& f) {
  if (s.rhs.empty()) return f;
  check<InputError>(f.size() == s.rows() && s.rhs.size() == s.col.size(), "average_rhs: ", f.size(), " values, ",
                    s.rows(), " rows, ", s.rhs.size(), " weights for ", s.col.size(), " entries (size mismatch)");
  Field out(s.rows());
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < s.rows(); ++i) {
    Real acc = 0;
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
      const Real mu = s.rhs[static_cast<std::size_t>(k)];
      if (mu != 0) acc += mu * f[s.col[static_cast<std::size_t>(k)]];  // f is read only where a row weighs it
    }
    out[i] = acc;
  }
  return out;
}

void require_point_rows(const Stencil& s, const std::string& use) {
  check<ConfigError>(s.rhs.empty(), use, ": the ", s.method, " rows carry right-hand-side weights (rhs=compact: L u "
                     "approximates an average of the operator over the stencil, not its value at the particle); use "
                     "rhs=point here");
}

SparseView as_eigen(const Stencil& s, int component) {
  check<InputError>(component >= 0 && component < s.components(), "as_eigen: component ", component,
                    " out of range for a stencil with ", s.components(), " components");
  return SparseView(s.rows(), s.rows(), s.nnz(), s.row_ptr.data(), s.col.data(),
                    s.values[static_cast<std::size_t>(component)].data());
}

}  // namespace vrsph
