// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Stencil: the one output shape of every method. A sparse linear operator over
// the particles in CSR form, (L u)_i = sum_k values[c][k] * u[col[k]] for k in row i.
//
// Sign convention: the stored stencil approximates the operator itself, with its
// natural sign. A Laplacian or div(a grad) stencil therefore has non-positive
// diagonal and, for monotone methods (SPH/Morris, VRSPH), non-negative off-diagonal
// entries: it is -L that is (up to boundary rows) an M-matrix. Operators that are
// exact on constants are stored in difference form, L_ii = -sum_{j != i} L_ij.
//
// Shapes: row_ptr has rows()+1 entries; col (sorted within each row, always
// containing the diagonal) and every values[c] have nnz() entries. Vector
// operators (Gradient) keep dim value arrays over one shared pattern.
#include <span>
#include <string>
#include <vrsph/core/types.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>
#include <vrsph/stencil/operator_kind.hpp>

namespace vrsph {

struct Stencil {
  OperatorKind kind = OperatorKind::Laplacian;
  int dim = 2;
  std::string method;                    ///< registry name of the method that built it
  std::vector<Index> row_ptr{0};
  std::vector<Index> col;
  std::vector<Index> diag;               ///< position in col of the diagonal of each row
  std::vector<std::vector<Real>> values; ///< components(kind, dim) arrays
  /// Per-row residual of the method's local problem (VRSPH: ||A v - b||_2 of the moment
  /// system, |b| = sqrt(d)); empty for methods without one.
  std::vector<Real> residual;
  /// Per-row flag: the local solve failed (e.g. NNLS iteration cap, a singular Taylor
  /// system under on_singular=warn; such rows are left zero); empty if none.
  std::vector<char> local_failure;
  /// Per-row condition number estimate of the method's local square system after
  /// row/column equilibration (FPM, KGF, CSPM, RKPM, [AAR] FPM variants); empty for
  /// methods without one.
  std::vector<Real> condition;
  /// Per-row monotonicity diagnostic of the [SPE] schemes (94): max_J ξ_I·Δ_J with
  /// ξ_I = C_Iᵀ Ñ_I. The factors 1 - ξ_I·Δ_J of S/M-SPH are all positive iff it is < 1
  /// ((93)); empty for other methods.
  std::vector<Real> xi;
  /// Per-row wall flux c_i >= 0 of a balance row (VRSPH flux=balance), empty if none: at a
  /// Neumann particle with c_i > 0 the Laplacian / div(a grad) row approximates
  /// div(a grad u)_i - c_i q_i, q = a ∂u/∂n (n·M grad u with a mobility), so the assembly
  /// moves c_i q_i to the right-hand side instead of using a gradient (flux) row.
  std::vector<Real> wall_flux;
  /// Per-row count of negative volumes a row took to meet its moment conditions (VRSPH
  /// boundary=signed), empty if none: such rows lose the M-matrix sign structure.
  std::vector<int> negative_volumes;
  /// Right-hand-side weights on the same pattern as col (VRSPH rhs=compact), empty if none:
  /// row i then approximates Σ_k rhs[k] (L u)(x_col[k]) rather than (L u)(x_i), so a boundary
  /// value problem's right-hand side is Σ_k rhs[k] f[col[k]] instead of f_i.
  std::vector<Real> rhs;

  Index rows() const { return static_cast<Index>(row_ptr.size()) - 1; }
  Index nnz() const { return row_ptr.back(); }
  int components() const { return static_cast<int>(values.size()); }
  Index row_begin(Index i) const { return row_ptr[static_cast<std::size_t>(i)]; }
  Index row_end(Index i) const { return row_ptr[static_cast<std::size_t>(i) + 1]; }
};

/// Pattern {i} ∪ N_i for every row (sorted, diagonal included), all values zero.
Stencil make_stencil_pattern(const NeighbourList& neighbours, OperatorKind kind, int dim, std::string method);
/// `s` made a fresh stencil of this kind, dimension and method whose arrays keep their storage
/// (row_ptr, col, diag, values as they were; every per-row output of a previous build cleared):
/// what a rebuild into the same object starts from.
void reset_stencil(Stencil& s, OperatorKind kind, int dim, std::string method);
/// The same into `s`, whose storage is reused (a rebuild on particles that moved); its other
/// per-row outputs (residual, rhs, ...) are cleared. zero_values = false leaves the values as
/// they were (resized): for a caller that writes every entry.
void fill_stencil_pattern(const NeighbourList& neighbours, OperatorKind kind, int dim, std::string method, Stencil& s,
                          bool zero_values = true);

/// Slot in the stencil row of i that holds neighbour number k of the neighbour list
/// (the neighbour row skips the diagonal, the stencil row does not).
inline Index neighbour_slot(const Stencil& s, Index i, Index k) {
  const Index pos = s.row_begin(i) + k;
  return pos >= s.diag[static_cast<std::size_t>(i)] ? pos + 1 : pos;
}

/// Row i of one component applied to a field: Σ_k values[component][k] u[col[k]], in row order
/// (the loop of apply and of the divergence and curl).
inline Real row_product(const Stencil& s, int component, Index i, const Real* u) {
  const auto& v = s.values[static_cast<std::size_t>(component)];
  Real acc = 0;
  for (Index k = s.row_begin(i); k < s.row_end(i); ++k) acc += v[static_cast<std::size_t>(k)] * u[s.col[static_cast<std::size_t>(k)]];
  return acc;
}

/// A row of its own pattern that replace_rows puts in place of a stencil's row: its columns
/// (sorted, distinct, the row's own index included), one value array per component of the
/// stencil and, when the stencil has right-hand-side weights, those, all aligned with `col`.
struct RowReplacement {
  Index row = 0;
  std::vector<Index> col;
  std::vector<std::vector<Real>> values;
  std::vector<Real> rhs;
};
/// Replaces the rows named in `rows` (sorted by row, each once) with their own patterns and
/// values; the other rows, and every per-row array, stay as they are. What a method uses when
/// a few rows reach beyond the neighbour list that gave the stencil its pattern (VRSPH's
/// compact rows on a wider support). InputError for a malformed replacement.
void replace_rows(Stencil& s, std::span<const RowReplacement> rows);

/// Sets L_ii = -sum_{j != i} L_ij in every component and row (difference form).
void set_difference_diagonal(Stencil& s);

}  // namespace vrsph
