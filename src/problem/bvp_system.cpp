// SPDX-License-Identifier: BSD-3-Clause
// Stages 7-9 of the solve pipeline (bvp_pipeline.hpp): this rank's rows of the linear system
// (columns numbered over every rank), its solve, and the solution back in the chunk's order.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/solve/solver.hpp>
#include <vrsph/stencil/apply.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph::detail {

namespace {
// Some data anywhere, and every owned unknown connected through non-zero entries to a row
// coupled to data (else the system is singular); the whole-cloud assembly checks this itself.
void check_anchored_over_ranks(const Partition& part, const LinearSystem& sys, bool neumann, bool robin, bool pinned) {
  const Communicator& comm = part.comm();
  const PointCloud& cloud = part.local();
  const Index n = cloud.size(), m = sys.rows_owned;
  const long long unknowns = sum_over_ranks(comm, static_cast<long long>(m));
  const long long known = sum_over_ranks(comm, static_cast<long long>(cloud.count(Tag::Dirichlet)));
  const bool anchored_somewhere = known > 0 || any_rank(comm, pinned) || any_rank(comm, robin);
  collective(comm, [&] {
    check<InputError>(unknowns > 0, "the problem has no unknown (interior) particle");
    check<InputError>(anchored_somewhere, neumann ? "only Neumann data and no Dirichlet particle: the solution is "
                                                    "determined only up to a constant (singular system); fix the "
                                                    "constant (--fix-constant)"
                                                  : "the cloud has no Dirichlet particle: the problem is singular");
  });
  std::vector<Index> offsets(static_cast<std::size_t>(n) + 1, 0), targets;
  std::vector<char> seeds(static_cast<std::size_t>(n), 0);
  std::vector<Index> row_of(static_cast<std::size_t>(n), -1);
  for (Index d = 0; d < m; ++d) row_of[static_cast<std::size_t>(sys.particle_of_dof[static_cast<std::size_t>(d)])] = d;
  for (Index i = 0; i < n; ++i) {
    const Index d = row_of[static_cast<std::size_t>(i)];
    if (d >= 0) {
      seeds[static_cast<std::size_t>(i)] = sys.anchored[static_cast<std::size_t>(d)];
      for (Index k = sys.A.outerIndexPtr()[d]; k < sys.A.outerIndexPtr()[d + 1]; ++k) {
        const Index j = sys.particle_of_dof[static_cast<std::size_t>(sys.A.innerIndexPtr()[k])];
        if (j != i && sys.A.valuePtr()[k] != 0) targets.push_back(j);
      }
    }
    offsets[static_cast<std::size_t>(i) + 1] = static_cast<Index>(targets.size());
  }
  const std::vector<char> reached = part.reach(offsets, targets, std::move(seeds));
  // The first id as a double (exact below 2^53), +inf where none floats: converted back only when
  // one does. (The largest long long as the sentinel came back from the double reduction as 2^63,
  // outside long long: undefined behaviour, which UBSan reported on every connected system.)
  long long floating = 0;
  double first = std::numeric_limits<double>::infinity();
  for (Index d = 0; d < m; ++d) {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    if (!reached[static_cast<std::size_t>(i)]) {
      ++floating;
      first = std::min(first, static_cast<double>(part.global_id(i)));
    }
  }
  floating = sum_over_ranks(comm, floating);
  first = min_over_ranks(comm, first);
  const long long first_id = floating > 0 ? static_cast<long long>(first) : -1;
  collective(comm, [&] {
    check<GeometryError>(floating == 0, floating, " unknown particle(s) are not connected to any Dirichlet particle "
                         "(singular system); first: particle ", first_id);
  });
}

}  // namespace

// The interior particle nearest the centre of the domain (or of the interior particles) over
// every rank: it pins the constant of a pure-Neumann problem. Ties: the smallest global id,
// as a serial search keeps the first.
Index centre_particle(const Partition& part, const std::vector<char>& interior) {
  const PointCloud& cloud = part.local();
  const Communicator& comm = part.comm();
  Vec3 centre = Vec3::Zero();
  if (cloud.domain.shape == Domain::Shape::Ball) {
    centre = cloud.domain.centre;
  } else if (cloud.domain.shape == Domain::Shape::Box) {
    centre = 0.5 * (cloud.domain.lo + cloud.domain.hi);
  } else {
    long long count = 0;
    for (Index i = 0; i < cloud.size(); ++i)
      if (interior[static_cast<std::size_t>(i)]) {
        centre += cloud.positions[static_cast<std::size_t>(i)];
        ++count;
      }
    for (int k = 0; k < 3; ++k) centre[k] = sum_over_ranks(comm, centre[k]);
    centre /= static_cast<Real>(std::max<long long>(sum_over_ranks(comm, count), 1));
  }
  Real best = std::numeric_limits<Real>::infinity();
  Index best_i = -1;
  for (Index i = 0; i < cloud.size(); ++i)
    if (interior[static_cast<std::size_t>(i)] && (cloud.positions[static_cast<std::size_t>(i)] - centre).norm() < best) {
      best = (cloud.positions[static_cast<std::size_t>(i)] - centre).norm();
      best_i = i;
    }
  const Real global_best = min_over_ranks(comm, best);
  const long long mine =
      best == global_best && best_i >= 0 ? part.global_id(best_i) : std::numeric_limits<long long>::max();
  const long long chosen = static_cast<long long>(-max_over_ranks(comm, -static_cast<double>(mine)));
  return best_i >= 0 && part.global_id(best_i) == chosen ? best_i : -1;
}

// This rank's rows with their columns renumbered from local dofs to global ones (sorted
// again: the halo dofs' global numbers need not follow the local order).
LinearSystem globalise(const Partition& part, LinearSystem sys) {
  const Index m = sys.rows_owned, n = part.local_size();
  const long long unknowns = sum_over_ranks(part.comm(), static_cast<long long>(m));
  const Index first_dof = static_cast<Index>(offset_over_ranks(part.comm(), m));
  std::vector<Index> global_dof(static_cast<std::size_t>(n), -1);
  for (Index d = 0; d < m; ++d) global_dof[static_cast<std::size_t>(sys.particle_of_dof[static_cast<std::size_t>(d)])] = first_dof + d;
  part.update_halo(global_dof);
  LinearSystem out;
  out.A.resize(m, static_cast<Index>(unknowns));
  out.A.resizeNonZeros(sys.A.nonZeros());
  std::copy(sys.A.outerIndexPtr(), sys.A.outerIndexPtr() + m + 1, out.A.outerIndexPtr());
  std::vector<std::pair<Index, Real>> row;
  for (Index d = 0; d < m; ++d) {
    row.clear();
    for (Index k = sys.A.outerIndexPtr()[d]; k < sys.A.outerIndexPtr()[d + 1]; ++k) {
      const Index j = sys.particle_of_dof[static_cast<std::size_t>(sys.A.innerIndexPtr()[k])];
      row.emplace_back(global_dof[static_cast<std::size_t>(j)], sys.A.valuePtr()[k]);
    }
    std::sort(row.begin(), row.end());
    Index at = sys.A.outerIndexPtr()[d];
    for (const auto& [c, v] : row) {
      out.A.innerIndexPtr()[at] = c;
      out.A.valuePtr()[at++] = v;
    }
  }
  out.b = std::move(sys.b);
  out.known = std::move(sys.known);
  out.particle_of_dof.assign(sys.particle_of_dof.begin(), sys.particle_of_dof.begin() + m);
  out.rows_owned = m;
  return out;
}

LinearSystem assemble_over_ranks(const Partition& part, const Stencil& L, const RowMasks& masks, const Field& f,
                                const Field& g, const BoundaryRows& bc) {
  if (!part.has_halo()) return assemble(L, part.local(), masks.unknown, f, g, &bc);
  const AssemblyScope scope{masks.unknown};
  LinearSystem sys;
  part.stage([&] {
    fault_point(part.comm(), "assemble");
    sys = assemble(L, part.local(), masks.unknown_columns, f, g, &bc, &scope);
  });
  const bool robin = bc.robin.size() > 0 && bc.robin.maxCoeff() > 0;
  const bool neumann = any_rank(part.comm(), bc.gradient != nullptr || !L.wall_flux.empty());
  if (!bc.unanchored_ok) check_anchored_over_ranks(part, sys, neumann, robin, bc.pinned >= 0);
  return sys;
}

Index pinned_particle(const Partition& part, const RowMasks& masks, const BoundaryValueProblem& p,
                      const ProblemFields& given) {
  if (p.pinned >= 0) return p.pinned;
  return p.fix_constant || given.periodic_without_boundary ? centre_particle(part, masks.interior) : -1;
}

LinearSystem assemble_owned_rows(const Partition& part, const OperatorRows& r, const RowMasks& masks,
                                 const LocalData& data, Index pinned, const ProblemFields& given, BvpSolution& s) {
  const bool tensor = given.tensor;
  BoundaryRows bc;
  if (s.neumann_particles > 0) {
    bc.gradient = r.balance ? nullptr : &r.G;
    bc.coefficient = tensor ? nullptr : &data.a;
    bc.mobility = tensor ? &data.mobility : nullptr;
    bc.q = data.q;
    bc.robin = data.robin;
  }
  bc.pinned = pinned;
  LinearSystem sys = assemble_over_ranks(part, r.L, masks, data.f(), data.g(), bc);
  if (part.has_halo()) sys = globalise(part, std::move(sys));
  s.unknowns = static_cast<Index>(part.has_halo() ? sys.A.cols() : sys.size());
  s.nnz_per_row = static_cast<Real>(sum_over_ranks(part.comm(), static_cast<long long>(sys.A.nonZeros()))) /
                  static_cast<Real>(std::max<Index>(s.unknowns, 1));
  return sys;
}

SparseMatrix kept_operator_rows(const Partition& part, const Stencil& L) {
  if (!part.has_halo()) return as_eigen(L);
  const SparseView local = as_eigen(L);
  std::vector<Eigen::Triplet<Real>> entries;
  entries.reserve(static_cast<std::size_t>(local.nonZeros()));
  for (Index i = 0; i < part.local_size(); ++i) {
    if (!part.owned()[static_cast<std::size_t>(i)]) continue;
    for (SparseView::InnerIterator it(local, i); it; ++it)
      entries.emplace_back(static_cast<Index>(part.global_id(i)), static_cast<Index>(part.global_id(static_cast<Index>(it.col()))), it.value());
  }
  SparseMatrix out(part.global_size(), part.global_size());
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

Eigen::VectorXd solve_system(const Partition& part, const LinearSystem& sys, const BvpSolveOptions& o, BvpSolution& s) {
  const Communicator& comm = part.comm();
  SolverOptions solver = o.solver;
  solver.communicator = comm;
  if (solver.dimension == 0) solver.dimension = part.local().dim;
  Eigen::VectorXd x;
  // PETSc's own collectives run inside: a failure on one rank cannot be agreed on there.
  collective_or_abort(comm, [&] {
    fault_point(comm, "solve");
    s.solve = solve(sys, x, solver);
  });
  s.seconds_solve = max_over_ranks(comm, s.solve.seconds);
  s.warnings.insert(s.warnings.end(), s.solve.warnings.begin(), s.solve.warnings.end());
  collective(comm, [&] {
    if (!s.solve.success)
      throw NumericalError(concat("solver ", s.solve.solver, " failed for ", label_of(o), ": ", s.solve.message,
                                  " (relative residual ", s.solve.residual, ")",
                                  std::isfinite(s.solve.residual) ? "" : "; the arithmetic overflowed: coefficient, "
                                  "mobility or data near the floating-point range? rescale the problem"));
  });
  return x;
}

void report_solution(const Partition& part, const LinearSystem& sys, const Eigen::VectorXd& x, const LocalData& data,
                     Real spacing, BvpSolution& s) {
  const Index m = sys.rows_owned >= 0 ? sys.rows_owned : sys.size();
  Field u = sys.known;
  for (Index d = 0; d < m; ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
  s.u = part.to_chunk(std::move(u));
  s.local_residual = part.to_chunk(std::move(s.local_residual));
  if (any_rank(part.comm(), s.wall_flux.size() > 0)) s.wall_flux = part.to_chunk(std::move(s.wall_flux));
  // With only Neumann data a solution exists only if the boundary flux equals the source
  // (divergence theorem). Without a domain description both integrals are estimated by
  // particle quadrature: volume dx^d per interior particle (half at Neumann particles, which
  // sit on the boundary), area dx^(d-1) per Neumann particle. That is first-order accurate,
  // so only a clear imbalance is reported (> 20 % of the scale).
  const Communicator& comm = part.comm();
  const PointCloud& cloud = part.local();
  const bool robin = data.robin.size() > 0 && data.robin.maxCoeff() > 0;
  if (s.neumann_particles == 0 || any_rank(comm, cloud.count(Tag::Dirichlet) > 0) || any_rank(comm, robin)) return;
  const Real volume = std::pow(spacing, cloud.dim), area = std::pow(spacing, cloud.dim - 1);
  std::vector<double> sums(3, 0.0);  // source, flux, scale
  for (Index i = 0; i < cloud.size(); ++i) {
    if (!part.owned()[static_cast<std::size_t>(i)]) continue;
    const Tag t = cloud.tags[static_cast<std::size_t>(i)];
    if (t == Tag::Interior || t == Tag::Neumann) {
      const Real v = t == Tag::Interior ? volume : 0.5 * volume;
      sums[0] += v * data.f()[i];
      sums[2] += v * std::abs(data.f()[i]);
    }
    if (t == Tag::Neumann) {
      sums[1] += area * data.q[i];
      sums[2] += area * std::abs(data.q[i]);
    }
  }
  sum_over_ranks(comm, sums);
  s.neumann_imbalance = std::abs(sums[1] - sums[0]) / std::max(sums[2], std::numeric_limits<Real>::min());
  if (s.neumann_imbalance > 0.2)
    s.warnings.push_back(concat(
        "only Neumann data, and they do not balance the source: boundary flux ~ ", sums[1], " but integral of f ~ ",
        sums[0], " (particle quadrature; ", s.neumann_imbalance, " of their size); a solution exists only if they are "
        "equal, so this one is not meaningful: check q and f"));
}

}  // namespace vrsph::detail
