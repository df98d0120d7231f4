#pragma once
// Volume reconstruction (VRSPH, [QW] §4): for every centre i separately, non-negative
// quadrature weights v^(i)_j on its neighbours that satisfy the moment conditions,
// by NNLS. Weights are stored aligned with the neighbour list (slot k of row i).
#include <span>
#include <vrsph/core/uninitialized.hpp>
#include <vrsph/methods/method.hpp>
#include <vrsph/methods/vrsph/moments.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>

namespace vrsph {

struct ReconstructedVolumes {
  MomentConditions conditions = MomentConditions::Laplace;
  UninitVector<Real> v;            ///< size neighbours.total(); rows not computed hold 0
  std::vector<Real> residual;      ///< ||A v - b||_2 per row (0 for rows not computed)
  std::vector<char> failed;        ///< 1 where NNLS hit its iteration cap
  std::vector<int> iterations;     ///< NNLS iterations per row
  std::vector<int> positive;       ///< number of v_j > 0 per row
};

/// The neighbour geometry of particle i that its moment system is built from:
/// xji[k] = x_j - x_i and half_y[k] = Y_ij / 2 = -W'(r_ij)/r_ij for its k-th neighbour j
/// (both arrays hold neighbours.count(i) entries). ker: the kernel of row i.
void neighbour_geometry(const Discretisation& disc, Index i, const Kernel& ker, Vec3* xji, Real* half_y);

/// rows: which particles need volumes (empty = every non-ghost particle).
/// The residual is reported for the literal (Full) system in either layout: merging
/// identical rows leaves ||A v - b|| unchanged.
/// targets: per-particle anisotropic Laplace targets (size N; empty = the Laplacian's).
ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows = {}, const NnlsOptions& nnls = {},
                                         MomentRows layout = MomentRows::Merged,
                                         std::span<const MomentTarget> targets = {});

}  // namespace vrsph
