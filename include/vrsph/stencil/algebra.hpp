// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Stencil algebra: building a stencil from a sparse matrix, and the nested second
// derivative sum_a D_a (c D_a) of methods that obtain second derivatives by applying a
// first-derivative stencil twice ([AAR](12), (26): original SPH, RKPM). Those stencils
// reach two neighbour rings, so their pattern is not the neighbour list. Splicing: one
// stencil's rows replaced by another's at chosen particles.
#include <span>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

/// Copies a row-major sparse matrix into a one-component stencil (columns sorted,
/// a diagonal slot inserted where the matrix has none).
Stencil stencil_from_matrix(const SparseMatrix& m, OperatorKind kind, int dim, std::string method);

/// sum over the d components of a gradient stencil G of G_a diag(c) G_a (c empty: 1),
/// keeping only the rows with rows[i] != 0 (others empty). G must have its rows
/// computed for every particle a kept row couples to.
Stencil nested_second_derivative(const Stencil& gradient, const Field* coefficient, std::span<const char> rows,
                                 OperatorKind kind);

/// `base` with its rows at the particles where rows[i] != 0 taken from `from`, into `out` (whose
/// storage is reused): e.g. a flow's gradient with linear-fit rows at its free surface. Both
/// of one kind, dimension, size and component count; the patterns may differ. Per-row outputs
/// (residual, condition, local_failure, ...) follow their rows, 0 in the rows of a stencil that
/// has none; right-hand-side weights (rhs) likewise, a row without them taking the identity.
/// `out.method` is base's. InputError on a shape mismatch.
void splice_rows(const Stencil& base, const Stencil& from, std::span<const char> rows, Stencil& out);

}  // namespace vrsph
