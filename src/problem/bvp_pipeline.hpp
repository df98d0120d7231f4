// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the stages of vrsph::solve (solve_bvp.cpp), one data path for 1..P ranks. Each
// stage works on a Partition (parallel/partition.hpp): in serial the whole cloud, every
// exchange the identity; under MPI one rank's owned particles and halo.
//
//   check_problem -> choose_support (+ the partition) -> local_data -> find_local_neighbours
//   -> build_operator_rows -> diagnose_rows -> assemble_owned_rows -> solve_system
//   -> report_solution
//
// A stage that can fail on one rank runs through Partition::stage (collective: the same
// typed exception on every rank, naming global particle numbers).
#include <memory>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/methods/method.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include "../parallel/partition.hpp"

namespace vrsph::detail {

/// Which optional fields the problem gives (agreed over the ranks: a chunk may be empty).
struct ProblemFields {
  bool a = false, grad_a = false, tensor = false, q = false, robin = false;
  /// A box periodic along every axis without Dirichlet or Neumann particles: u is fixed up
  /// to a constant, pinned at one particle for the solve and then shifted to zero mean.
  bool periodic_without_boundary = false;
};

/// The support radius: h, per-particle radii (knn), the spacing it came from.
struct Support {
  Real spacing = 0, h = 0, covering_radius = 0;
  std::vector<Real> radii;  ///< per local particle (knn), else empty
};

/// The problem's data at the local particles (owned and halo). f and g are read in place
/// in serial (the whole cloud's own fields: no copy of two values per particle).
struct LocalData {
  Field a, q, robin;
  Eigen::MatrixXd mobility, grad_a;
  const Field& f() const { return f_in_place ? *f_in_place : f_local; }
  const Field& g() const { return g_in_place ? *g_in_place : g_local; }
  Field f_local, g_local;
  const Field* f_in_place = nullptr;
  const Field* g_in_place = nullptr;
};

/// Row masks over the local particles: the owned interior, Neumann and unknown particles,
/// and every local unknown (the columns, halo copies included).
struct RowMasks {
  std::vector<char> interior, flux, unknown, unknown_columns;
};

/// The operator rows: div(a grad) on the interior (and, with balance rows, Neumann)
/// particles; the method's gradient on Neumann rows otherwise.
struct OperatorRows {
  Stencil L, G;
  bool balance = false;
  const std::vector<char>& rows(const RowMasks& m) const { return balance ? m.unknown : m.interior; }
};

std::string label_of(const BvpSolveOptions& o);

ProblemFields check_problem(const BoundaryValueProblem& p, const BvpSolveOptions& o);
/// The spacing, the support radius and the partition whose halo holds every row's reach.
std::unique_ptr<Partition> choose_support(const PointCloud& chunk, const BvpSolveOptions& o, Real reach, Support& support);
LocalData local_data(const Partition& part, const BoundaryValueProblem& p, const ProblemFields& given);
RowMasks row_masks(const Partition& part);
NeighbourList find_local_neighbours(const Partition& part, const Support& support, const RowMasks& masks);
/// Neighbours per unknown row, over every rank.
Real mean_neighbours(const Partition& part, const NeighbourList& nl, const RowMasks& masks);
/// The method's rows on the local particles: the cloud, its neighbours, and for MPI the whole
/// cloud's size and length unit (serial: taken from the cloud itself).
Discretisation local_discretisation(const Partition& part, const NeighbourList& nl, KernelType kernel, Real spacing);
/// `neumann`: Neumann particles on some rank; `name`: the method's name in messages; `use`:
/// System for a boundary value problem.
OperatorRows build_operator_rows(const Partition& part, const Method& method, const Discretisation& disc,
                                 const LocalData& data, const RowMasks& masks, bool neumann, const std::string& name,
                                 StencilUse use);
/// chain_anchor: a particle that anchors the M-matrix's chains as a Dirichlet row would (the
/// pin of a fully periodic problem, whose -L is otherwise singular); -1: none.
void diagnose_rows(const Partition& part, const Method& method, const OperatorRows& rows, const RowMasks& masks,
                   const LocalData& data, Index chain_anchor, const BvpSolveOptions& o, BvpSolution& s);
/// assemble() over the partition: the whole system with assemble()'s own checks in serial;
/// under MPI this rank's rows (local columns, AssemblyScope), the data anchoring every
/// unknown checked over the ranks.
LinearSystem assemble_over_ranks(const Partition& part, const Stencil& L, const RowMasks& masks, const Field& f,
                                const Field& g, const BoundaryRows& bc);
/// This rank's rows with their columns renumbered from local dofs to global ones.
LinearSystem globalise(const Partition& part, LinearSystem local);
/// The interior particle nearest the domain's centre (the one fix_constant pins), on the
/// rank that owns it (-1 on the others).
Index centre_particle(const Partition& part, const std::vector<char>& interior);
/// The particle whose row becomes u = g (local; -1: none, or another rank's): the problem's
/// own `pinned`, else the centre particle with fix_constant or a fully periodic problem.
Index pinned_particle(const Partition& part, const RowMasks& masks, const BoundaryValueProblem& p,
                      const ProblemFields& given);
/// This rank's rows of the system, columns numbered over every rank (serial: the system).
LinearSystem assemble_owned_rows(const Partition& part, const OperatorRows& rows, const RowMasks& masks,
                                 const LocalData& data, Index pinned, const ProblemFields& given, BvpSolution& s);
Eigen::VectorXd solve_system(const Partition& part, const LinearSystem& sys, const BvpSolveOptions& o, BvpSolution& s);
/// The operator rows a caller keeps (BvpSolveOptions::keep_matrices), rows and columns in
/// the whole cloud's particle numbers: serial, every row; under MPI the rows this rank owns
/// (each row on exactly one rank, the others empty).
SparseMatrix kept_operator_rows(const Partition& part, const Stencil& L);
/// Fully periodic problems (bvp_periodic.cpp): the equation the pin replaces, kept before
/// the rows are freed, and the correction that spreads its defect evenly.
struct PinnedRow {
  Index particle = -1;                         ///< local; -1: no pin here
  std::vector<std::pair<Index, Real>> entries; ///< (local particle, L_pj)
  Real rhs = 0;                                ///< f_p, or the compact row's average of f
};
PinnedRow pinned_row(const Stencil& L, const LocalData& data, Index pinned);
void spread_periodic_defect(const Partition& part, LinearSystem& sys, const PinnedRow& row, const Field& f_owned,
                            const BvpSolveOptions& o, Eigen::VectorXd& x, BvpSolution& s);
/// u and the local residuals back in the chunk's order; the Neumann solvability warning.
void report_solution(const Partition& part, const LinearSystem& sys, const Eigen::VectorXd& x, const LocalData& data,
                     Real spacing, BvpSolution& s);

}  // namespace vrsph::detail
