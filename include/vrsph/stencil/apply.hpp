// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Applying a stencil, and viewing it as an Eigen sparse matrix without copying.
#include <Eigen/SparseCore>
#include <vrsph/stencil/stencil.hpp>

namespace vrsph {

using SparseMatrix = Eigen::SparseMatrix<Real, Eigen::RowMajor, Index>;
using SparseView = Eigen::Map<const SparseMatrix>;

/// (L u) for every component: an N x components() matrix. Throws InputError on a size mismatch.
Eigen::MatrixXd apply(const Stencil& s, const Field& u);
/// One component only.
Field apply_component(const Stencil& s, const Field& u, int component);
/// The right-hand-side average a row stands for (Stencil::rhs): Σ_k rhs[k] f[col[k]] per
/// row over its non-zero weights, or f itself when the stencil has no such weights.
Field average_rhs(const Stencil& s, const Field& f);
/// ConfigError naming `use` when the stencil has right-hand-side weights (compact rows),
/// for uses that take L u as the operator's value at each particle (spectra, time steps).
void require_point_rows(const Stencil& s, const std::string& use);
/// Zero-copy view of one component (the stencil must outlive the view).
SparseView as_eigen(const Stencil& s, int component = 0);

}  // namespace vrsph
