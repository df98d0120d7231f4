// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Volume reconstruction (VRSPH, [QW] §4): for every centre i separately, non-negative
// quadrature weights v^(i)_j on its neighbours that satisfy the moment conditions,
// by NNLS. Weights are stored aligned with the neighbour list (slot k of row i).
#include <cstdint>
#include <span>
#include <vrsph/core/uninitialized.hpp>
#include <vrsph/methods/method.hpp>
#include <vrsph/methods/vrsph/moments.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>

namespace vrsph {

/// Each row's positive-volume neighbours as particle indices (at most `stride` per row): the NNLS
/// passive sets of a build, and the guess a rebuild on particles that have moved starts from
/// (VolumeOptions::warm_start). Particle indices, not slots: the neighbour lists change.
struct ActiveSets {
  int stride = 0;                    ///< entries kept per row (the moment rows: a passive set is no larger)
  std::vector<Index> particles;      ///< row i: particles[i * stride + 0 .. count[i])
  std::vector<std::uint8_t> count;   ///< per row (empty: no sets)
  bool empty() const { return count.empty(); }
};

struct ReconstructedVolumes {
  MomentConditions conditions = MomentConditions::Laplace;
  UninitVector<Real> v;            ///< size neighbours.total(); rows not computed hold 0
  std::vector<Real> residual;      ///< ||A v - b||_2 per row (0 for rows not computed)
  std::vector<char> failed;        ///< 1 where NNLS hit its iteration cap
  std::vector<int> iterations;     ///< NNLS iterations per row
  std::vector<int> positive;       ///< number of v_j > 0 per row
  std::vector<char> signed_row;    ///< 1 where InfeasibleRowPolicy::Signed replaced the NNLS volumes
  std::vector<int> negative;       ///< number of v_j < 0 per row (signed rows only)
  std::vector<Real> wall_flux;     ///< balance rows: c_i >= 0 of Σ w x_ji = first - c_i conormal_i; else empty
  Index warm_rows = 0;             ///< rows whose NNLS started from VolumeOptions::warm_start
  Index warm_hits = 0;             ///< of those, rows where the guess was optimal as it stood (no iteration)
  ActiveSets active;               ///< VolumeOptions::record_active: each row's positive volumes
};

/// What a row whose NNLS volumes leave the moment conditions unmet (relative residual
/// above VolumeOptions::signed_threshold) gets.
///  Keep:   the NNLS best fit (the paper's VRSPH; the row is reported infeasible).
///  Signed: exact moments with few, small negative volumes (signed_volumes.hpp); the row
///          loses the M-matrix sign structure.
enum class InfeasibleRowPolicy { Keep, Signed };

/// Balance rows at wall particles (VRSPH flux=balance): the WallLaplace conditions with one
/// more non-negative unknown, the wall flux c_i, entering the first moments along the
/// conormal: Σ_j w_j x_ji = first_i - c_i conormal_i, Σ_j w_j x_ji x_jiᵀ = 2 diag(second_i).
/// The row then approximates div(a grad u)_i - c_i (a ∂u/∂n)_i to O(h) (O(h^2) after
/// division by c_i ~ 1/h: the classic ghost-point Neumann row), and a Neumann or Robin
/// condition enters it as data.
struct WallRows {
  std::span<const char> rows;      ///< per particle: 1 = balance row (empty: none)
  std::span<const Vec3> conormal;  ///< per particle: n_i for a scalar a, M_i n_i for a mobility
};

struct VolumeOptions {
  NnlsOptions nnls;
  MomentRows layout = MomentRows::Merged;
  InfeasibleRowPolicy infeasible = InfeasibleRowPolicy::Keep;
  Real signed_threshold = 1e-10;  ///< relative residual ||A v - b|| / ||b|| beyond which a row is signed
  /// Scale the NNLS columns by (r_min / r_j)^2 so that its path prefers the nearest neighbours
  /// (same feasible set, another vertex; balance rows always do).
  bool prefer_near = false;
  WallRows wall;
  /// Interior rows start their NNLS from these sets (neighbours no longer in the row are
  /// dropped); null or empty: cold starts. Balance rows always start cold.
  const ActiveSets* warm_start = nullptr;
  /// Record each row's positive-volume neighbours in ReconstructedVolumes::active (the next
  /// rebuild's warm start).
  bool record_active = false;
};

/// The neighbour geometry of particle i that its moment system is built from:
/// xji[k] = (x_j - x_i) / length and half_y[k] = Y_ij / 2 length^(d+2) = -W'(r_ij)/r_ij
/// length^(d+2) for its k-th neighbour j (both arrays hold neighbours.count(i) entries), in
/// units of `length`. ker: the kernel of row i.
void neighbour_geometry(const Discretisation& disc, Index i, const Kernel& ker, Vec3* xji, Real* half_y,
                        Real length = 1);

/// rows: which particles need volumes (empty = every non-ghost particle).
/// The residual is reported for the literal (Full) system in either layout: merging
/// identical rows leaves ||A v - b|| unchanged.
/// targets: per-particle anisotropic Laplace targets (size N; empty = the Laplacian's).
ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows = {}, const NnlsOptions& nnls = {},
                                         MomentRows layout = MomentRows::Merged,
                                         std::span<const MomentTarget> targets = {});
/// The same with the policies for infeasible rows and balance rows (Laplace conditions only
/// for the latter two).
ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows, const VolumeOptions& options,
                                         std::span<const MomentTarget> targets = {});
/// The same into `out`, its storage reused (rebuilds on particles that moved).
void reconstruct_volumes(const Discretisation& disc, MomentConditions conditions, std::span<const char> rows,
                         const VolumeOptions& options, std::span<const MomentTarget> targets, ReconstructedVolumes& out);

}  // namespace vrsph
