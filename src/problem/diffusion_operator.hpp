// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the spatial operator of diffuse() (diffusion.cpp) over a Partition, built by the
// solve pipeline's stages (bvp_pipeline.hpp) and applied each time step. In serial the
// partition is the whole cloud; under MPI each rank steps its owned particles, the halo
// refreshed from their owners before every use.
#include <memory>
#include <vrsph/problem/diffusion.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph::detail {

struct DiffusionOperator {
  std::unique_ptr<Partition> part;
  RowMasks masks;
  LocalData data;         ///< a or the mobility at the local particles
  Stencil L, G;           ///< div(a grad) on the owned interior rows; the gradient on the owned Neumann rows
  bool neumann = false;   ///< Neumann particles on some rank
  Real spacing = 0, radius = 0;
  /// The owned rows over the unknowns (assembled for implicit schemes and Neumann rows):
  /// columns local dofs (owned first, then halo copies) in `local`, global ones in `global`
  /// (serial: the same system, kept once in `local`).
  LinearSystem local, global;
  const LinearSystem& system() const { return part->has_halo() ? global : local; }
  bool is_flux_dof(Index d) const {
    return masks.flux[static_cast<std::size_t>(local.particle_of_dof[static_cast<std::size_t>(d)])] != 0;
  }
  Index owned_dofs() const { return local.rows_owned >= 0 ? local.rows_owned : local.size(); }
};

/// Checks the method, builds the stencils and, for implicit schemes or Neumann rows, the system.
DiffusionOperator build_diffusion_operator(const DiffusionProblem& p, const DiffusionOptions& o);

/// u = g(x, t) at the local Dirichlet particles (halo included: g is a function of position).
void set_dirichlet_values(const DiffusionOperator& op, const DiffusionProblem& p, Real t, Field& u);

/// c(t) = sum over known J of A_iJ g_J(t) for each owned dof: the known neighbours' share of
/// each row (interior rows: L g; flux rows: n.M (G g)).
Eigen::VectorXd known_coupling(const DiffusionOperator& op, const DiffusionProblem& p, Real t);

/// The flux rows' block A_NN over the Neumann dofs of every rank (rows: this rank's), for the
/// explicit scheme, and the map from owned dof to block row (-1: not a flux dof).
struct NeumannBlock {
  CsrMatrix A;
  std::vector<Index> dofs;      ///< owned flux dofs, block row order
  std::vector<Index> block_of;  ///< per local particle: global block column, -1 if not a Neumann unknown
};
NeumannBlock neumann_block(const DiffusionOperator& op);

/// I - theta dt A on the interior rows, the flux rows as they are: the implicit step's matrix
/// (owned rows, global columns).
CsrMatrix implicit_matrix(const DiffusionOperator& op, Real theta, Real dt);

}  // namespace vrsph::detail
