// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <functional>
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

void replace_rows(Stencil& s, std::span<const RowReplacement> rows) {
  if (rows.empty()) return;
  const std::size_t ncomp = s.values.size();
  const bool with_rhs = !s.rhs.empty();
  Index last = -1;
  for (const RowReplacement& r : rows) {
    check<InputError>(r.row > last && r.row < s.rows(), "replace_rows: row ", r.row, " out of order or outside the ",
                      s.rows(), " rows of the stencil");
    last = r.row;
    check<InputError>(r.values.size() == ncomp && (!with_rhs || r.rhs.size() == r.col.size()),
                      "replace_rows: row ", r.row, " has ", r.values.size(), " value arrays for ", ncomp, " components",
                      with_rhs ? " or right-hand-side weights not aligned with its columns" : "");
    for (const auto& v : r.values)
      check<InputError>(v.size() == r.col.size(), "replace_rows: row ", r.row, " has ", v.size(), " values for ",
                        r.col.size(), " columns");
    check<InputError>(std::adjacent_find(r.col.begin(), r.col.end(), std::greater_equal<Index>()) == r.col.end() &&
                          std::binary_search(r.col.begin(), r.col.end(), r.row) &&
                          r.col.front() >= 0 && r.col.back() < s.rows(),
                      "replace_rows: row ", r.row, "'s columns must be sorted, distinct particles of the stencil (0 .. ",
                      s.rows() - 1, ") and include the row itself");
  }
  // The new row pointers; then the unchanged rows moved as blocks (between two replacements)
  // and the replaced rows written from their replacements.
  const Index n = s.rows();
  std::vector<Index> row_ptr(static_cast<std::size_t>(n) + 1, 0);
  std::size_t next = 0;
  for (Index i = 0; i < n; ++i) {
    const bool replaced = next < rows.size() && rows[next].row == i;
    const Index len = replaced ? static_cast<Index>(rows[next].col.size()) : s.row_end(i) - s.row_begin(i);
    next += replaced ? 1 : 0;
    row_ptr[static_cast<std::size_t>(i) + 1] = row_ptr[static_cast<std::size_t>(i)] + len;
  }
  const auto nnz = static_cast<std::size_t>(row_ptr[static_cast<std::size_t>(n)]);
  // In place: the unchanged blocks moving left go first, front to back, those moving right
  // next, back to front; neither can overwrite a block still to move (new and old starts are
  // both increasing). An array grows only when the new pattern is longer (a replaced row of a
  // positive compact row is shorter than its neighbour list, and patterns keep a sixteenth
  // spare capacity): no copy of the whole stencil, which at 10^6 particles is 0.6 GB.
  const auto grow = [&](auto& v) {
    if (v.size() >= nnz) return;
    v.reserve(nnz);  // exactly: a resize beyond the capacity would double it
    v.resize(nnz);
  };
  grow(s.col);
  for (auto& v : s.values) grow(v);
  if (with_rhs) grow(s.rhs);
  struct Block {
    Index first, end;  // rows [first, end) unchanged
  };
  std::vector<Block> blocks;
  Index from = 0;
  for (const RowReplacement& r : rows) {
    if (r.row > from) blocks.push_back({from, r.row});
    from = r.row + 1;
  }
  if (n > from) blocks.push_back({from, n});
  const auto move_block = [&](const Block& k, bool right) {
    const auto a = static_cast<std::ptrdiff_t>(s.row_begin(k.first)), b = static_cast<std::ptrdiff_t>(s.row_begin(k.end));
    const auto to = static_cast<std::ptrdiff_t>(row_ptr[static_cast<std::size_t>(k.first)]);
    const auto shift = [&](auto& v) {
      if (right) std::copy_backward(v.begin() + a, v.begin() + b, v.begin() + to + (b - a));
      else std::copy(v.begin() + a, v.begin() + b, v.begin() + to);
    };
    shift(s.col);
    for (auto& v : s.values) shift(v);
    if (with_rhs) shift(s.rhs);
    for (Index i = k.first; i < k.end; ++i)
      s.diag[static_cast<std::size_t>(i)] += row_ptr[static_cast<std::size_t>(i)] - s.row_begin(i);
  };
  const auto delta = [&](const Block& k) { return row_ptr[static_cast<std::size_t>(k.first)] - s.row_begin(k.first); };
  for (const Block& k : blocks)
    if (delta(k) < 0) move_block(k, false);
  for (auto k = blocks.rbegin(); k != blocks.rend(); ++k)
    if (delta(*k) > 0) move_block(*k, true);
  for (const RowReplacement& r : rows) {
    const auto to = static_cast<std::ptrdiff_t>(row_ptr[static_cast<std::size_t>(r.row)]);
    std::copy(r.col.begin(), r.col.end(), s.col.begin() + to);
    for (std::size_t c = 0; c < ncomp; ++c) std::copy(r.values[c].begin(), r.values[c].end(), s.values[c].begin() + to);
    if (with_rhs) std::copy(r.rhs.begin(), r.rhs.end(), s.rhs.begin() + to);
    s.diag[static_cast<std::size_t>(r.row)] =
        static_cast<Index>(to + (std::lower_bound(r.col.begin(), r.col.end(), r.row) - r.col.begin()));
  }
  s.row_ptr = std::move(row_ptr);
  s.col.resize(nnz);
  for (auto& v : s.values) v.resize(nnz);
  if (with_rhs) s.rhs.resize(nnz);
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
