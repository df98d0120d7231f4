// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Assembly of the boundary value problem  L u = f  (L a div(a grad) or Laplacian
// stencil) into a linear system over the unknown particles.
//
// Unknowns are the particles with unknown[i] = 1 (Interior in the studies). Every other
// particle is known: its value (Dirichlet data g, or exact values at ghosts) moves to
// the right-hand side, [QW](4.5):  sum_{j unknown} L_ij U_j = f_i - sum_{j known} L_ij g_j.
// The diagonal L_ii already contains the weights of boundary neighbours (difference
// form).
//
// Neumann particles (Tag::Neumann, unknown) get the flux row a_i n_i · (G u)_i = q_i (plus
// β_i u_i with Robin data, BoundaryRows::robin) built
// from the method's own gradient stencil G ([AAR] §4 / METHODS §4: "the method's own
// first-derivative row"; [SPE](100) in 2D/3D), n_i the particle's outward normal. Known
// neighbours of a flux row move to the right-hand side like any other. A problem without
// Dirichlet particles is singular (constant null space) unless one unknown is pinned to
// its value g (BoundaryRows::pinned).
#include <span>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

/// Compressed sparse rows with sorted column indices: the layout the assembly fills row by
/// row in parallel and that PETSc's AIJ matrices use as they are (no copy).
using CsrMatrix = Eigen::SparseMatrix<Real, Eigen::RowMajor, Index>;

struct LinearSystem {
  CsrMatrix A;                         ///< unknowns x unknowns
  Eigen::VectorXd b;
  std::vector<Index> dof_of_particle;  ///< -1 for known particles
  std::vector<Index> particle_of_dof;
  Field known;                         ///< g at known particles, 0 at unknowns
  Index size() const { return static_cast<Index>(particle_of_dof.size()); }
  Index rows_owned = -1;               ///< AssemblyScope: the assembled rows (dofs 0..rows_owned-1); -1: all
  std::vector<char> anchored;          ///< AssemblyScope: per assembled row, coupled to data (Dirichlet, pinned, Robin)
};

/// Flux rows of the Neumann particles and the optional pinned particle.
struct BoundaryRows {
  const Stencil* gradient = nullptr;  ///< the method's Gradient stencil, rows of the Neumann particles computed
  Field q;                            ///< flux data a ∂u/∂n at every particle (used at Neumann particles)
  const Field* coefficient = nullptr; ///< a at every particle (nullptr: a = 1)
  /// Diagonal mobility (N x dim) instead of a: the flux row is n_i·M_i (G u)_i = q_i.
  const Eigen::MatrixXd* mobility = nullptr;
  Index pinned = -1;                  ///< unknown particle whose row becomes U = g (fixes a pure-Neumann constant)
  /// The rows are a part of a nonsingular operator (diffusion: I - θ dt L): no data need to
  /// anchor them, so the checks that every unknown reaches a Dirichlet/pinned/Robin row are skipped.
  bool unanchored_ok = false;
  /// Robin coefficient β >= 0 at every particle (empty: none): a Neumann particle's flux row
  /// becomes a_i n_i·(G u)_i + β_i u_i = q_i. A row with β > 0 fixes the level of u, so
  /// Robin data alone make the problem well-posed.
  Field robin;
};

/// One rank's part of a distributed system: only the rows of the particles with rows[i] = 1
/// (unknowns this rank owns) are assembled. Their dofs come first (0..rows-1, in particle
/// order), every other unknown (a halo copy) after them, so A is rows x all unknowns. The
/// global checks (some known particle, connectivity) are the caller's: they need every rank.
struct AssemblyScope {
  std::span<const char> rows;
};

/// f: right-hand side at every particle (used at unknowns); g: values at every particle
/// (used at known ones and at the pinned particle). Throws InputError (size mismatch,
/// non-finite data, no known particle, Neumann particle without normal or flux stencil),
/// ConfigError (vector stencil) or GeometryError (unknowns not connected through non-zero
/// weights to any known particle: singular system).
LinearSystem assemble(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f,
                      const Field& g, const BoundaryRows* boundary = nullptr, const AssemblyScope* scope = nullptr);

/// Full particle field: solution at unknowns, known values elsewhere.
Field expand(const LinearSystem& sys, const Eigen::VectorXd& x);

}  // namespace vrsph
