#pragma once
// Assembly of the boundary value problem  L u = f  (L a div(a grad) or Laplacian
// stencil) into a linear system over the unknown particles.
//
// Unknowns are the particles with unknown[i] = 1 (Interior in the studies). Every other
// particle is known: its value (Dirichlet data g, or exact values at ghosts) moves to
// the right-hand side, [QW](4.5):  sum_{j unknown} L_ij U_j = f_i - sum_{j known} L_ij g_j.
// The diagonal L_ii already contains the weights of boundary neighbours (difference
// form). Neumann/Robin rows replace a particle's row by a flux row and enter through the
// same mechanism in a later release; a Neumann-tagged particle is rejected for now.
#include <span>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

struct LinearSystem {
  Eigen::SparseMatrix<Real> A;       ///< unknowns x unknowns, column-major (solver format)
  Eigen::VectorXd b;
  std::vector<Index> dof_of_particle;  ///< -1 for known particles
  std::vector<Index> particle_of_dof;
  Field known;                         ///< g at known particles, 0 at unknowns
  Index size() const { return static_cast<Index>(particle_of_dof.size()); }
};

/// f: right-hand side at every particle (used at unknowns); g: values at every particle
/// (used at known ones). Throws InputError (size mismatch, non-finite data, no known
/// particle), ConfigError (Neumann particles, vector stencil) or GeometryError (unknowns
/// not connected through non-zero weights to any known particle: singular system).
LinearSystem assemble(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f,
                      const Field& g);

/// Full particle field: solution at unknowns, known values elsewhere.
Field expand(const LinearSystem& sys, const Eigen::VectorXd& x);

}  // namespace vrsph
