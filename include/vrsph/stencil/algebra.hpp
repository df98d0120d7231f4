// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Stencil algebra: building a stencil from a sparse matrix, and the nested second
// derivative sum_a D_a (c D_a) of methods that obtain second derivatives by applying a
// first-derivative stencil twice ([AAR](12), (26): original SPH, RKPM). Those stencils
// reach two neighbour rings, so their pattern is not the neighbour list.
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

}  // namespace vrsph
