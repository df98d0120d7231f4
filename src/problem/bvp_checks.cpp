// SPDX-License-Identifier: BSD-3-Clause
// Stage 1 of the solve pipeline (bvp_pipeline.hpp): the problem's fields and the options,
// checked before any work, on every rank's chunk.
#include <cmath>
#include <vrsph/core/error.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph::detail {

std::string label_of(const BvpSolveOptions& o) { return o.label.empty() ? o.method : o.label; }

namespace {
void check_size(const Field& v, Index n, const char* name, bool required, bool distributed) {
  if (v.size() == 0 && !required) return;
  check<InputError>(v.size() == n, "boundary value problem: ", name, " has ", v.size(), " values for ", n, " particles",
                    distributed ? " of this rank's part of the cloud" : "", " (size mismatch)");
}

void check_options(const BvpSolveOptions& o) {
  check<ConfigError>(std::isfinite(o.infeasible_tolerance) && o.infeasible_tolerance > 0,
                     "infeasible tolerance must be positive and finite, got ", o.infeasible_tolerance);
  check<ConfigError>(std::isfinite(o.h) && o.h >= 0, "support radius h must be >= 0 (0: from the h-factor), got ", o.h);
  if (o.h > 0) return;  // the h-factor and the h-mode are not used
  check<ConfigError>(std::isfinite(o.h_factor) && o.h_factor > 0, "h-factor must be positive and finite, got ", o.h_factor);
  check<ConfigError>(o.h_knn >= 0, "h-knn (k of the k-th neighbour) must be >= 1, or 0 for the default 2d; got ", o.h_knn);
}

// This chunk's fields against its particles.
void check_chunk(const BoundaryValueProblem& p, const BvpSolveOptions& o, bool tensor) {
  const Communicator& comm = o.communicator;
  const bool distributed = comm.distributed();
  if (!distributed) validate(p.cloud);  // distribute() validates each chunk (one may be empty)
  const Index n = p.cloud.size();
  check_size(p.a, n, "a", false, distributed);
  check_size(p.f, n, "f", true, distributed);
  check_size(p.g, n, "g", true, distributed);
  check_size(p.robin, n, "robin", false, distributed);
  check_size(p.q, n, "q", p.cloud.count(Tag::Neumann) > 0, distributed);
  check<InputError>(p.mobility.size() == 0 || p.mobility.rows() == n, "boundary value problem: the mobility has ",
                    p.mobility.rows(), " rows for ", n, " particles (size mismatch)");
  check<InputError>(!tensor || p.a.size() == 0, "boundary value problem: give either a scalar coefficient a or a "
                    "tensor mobility, not both");
  if (p.grad_a.size() && !tensor) {
    check<InputError>(p.grad_a.rows() == n && p.grad_a.cols() == p.cloud.dim, "grad_a must be ", n, " x ",
                      p.cloud.dim, ", got ", p.grad_a.rows(), " x ", p.grad_a.cols());
    check<InputError>(p.grad_a.allFinite(), "the gradient of the coefficient a is not finite");
  }
  check_options(o);
  check<ConfigError>(!distributed || p.pinned < 0, "BoundaryValueProblem::pinned names a particle of one rank's "
                     "part: with several ranks use fix_constant");
}
// div(a grad u) = f on a fully periodic box has a solution only if f integrates to zero.
// Particle quadrature with equal volumes (all that is known here) is crude on a disordered
// cloud: on smooth data with zero mean it measured 0.13 of the mean |f| at 4 particles per
// period (delta = 0.5), 3e-3 at 32. So only a mean above half the mean |f| is refused here
// (f = 1, f = 1 + sin 2 pi x); a smaller one is removed by the solve (the constant λ of
// spread_periodic_defect), with a warning when it is more than truncation.
void check_periodic_source(const BoundaryValueProblem& p, const Communicator& comm) {
  std::vector<double> sums{0.0, 0.0};
  for (Index i = 0; i < p.cloud.size(); ++i) {
    sums[0] += p.f[i];
    sums[1] += std::abs(p.f[i]);
  }
  sum_over_ranks(comm, sums);
  const auto n = static_cast<double>(std::max<long long>(1, sum_over_ranks(comm, static_cast<long long>(p.cloud.size()))));
  collective(comm, [&] {
    check<InputError>(std::abs(sums[0]) <= 0.5 * sums[1], "a fully periodic problem needs a source f with zero mean "
                      "(the integral of div(a grad u) over a period is zero); the mean of f over the particles is ",
                      sums[0] / n, ", ", std::abs(sums[0]) / std::max(sums[1], 1e-300),
                      " of the mean |f|: subtract it (or check f)");
  });
}
}  // namespace

ProblemFields check_problem(const BoundaryValueProblem& p, const BvpSolveOptions& o) {
  const Communicator& comm = o.communicator;
  ProblemFields given;
  given.tensor = any_rank(comm, p.mobility.size() > 0);
  collective(comm, [&] {
    fault_point(comm, "distribute");
    check_chunk(p, o, given.tensor);
  });
  given.a = any_rank(comm, p.a.size() > 0);
  given.grad_a = any_rank(comm, p.grad_a.size() > 0);
  given.q = any_rank(comm, p.q.size() > 0);
  given.robin = any_rank(comm, p.robin.size() > 0);
  const bool neumann_anywhere = any_rank(comm, p.cloud.count(Tag::Neumann) > 0);
  collective(comm, [&] {
    check<InputError>(!neumann_anywhere || given.q, "boundary value problem: Neumann particles need the flux q");
  });
  // A field given on some ranks' parts must be on every part that reads it. The flux data q
  // and β are read only at Neumann particles: a part without any may leave them empty and
  // gets zeros. a, ∇a and the mobility are read everywhere. (Serial: always true.)
  const Index n = p.cloud.size(), neumann = p.cloud.count(Tag::Neumann);
  collective(comm, [&] {
    const auto needed = [&](bool given_somewhere, bool given_here, bool read_here, const char* what) {
      check<InputError>(!given_somewhere || given_here || !read_here, "boundary value problem: ", what,
                        " is given on other ranks' parts but not on this rank's part (", n, " particles, ", neumann,
                        " Neumann); give it on every part that reads it");
    };
    needed(given.a, p.a.size() > 0, n > 0, "the coefficient a");
    needed(given.grad_a, p.grad_a.size() > 0, n > 0, "grad a");
    needed(given.tensor, p.mobility.size() > 0, n > 0, "the mobility");
    needed(given.robin, p.robin.size() > 0, neumann > 0, "the Robin coefficient");
  });
  given.periodic_without_boundary = p.cloud.domain.fully_periodic() && !neumann_anywhere &&
                                    !any_rank(comm, p.cloud.count(Tag::Dirichlet) > 0);
  if (given.periodic_without_boundary) check_periodic_source(p, comm);
  return given;
}

}  // namespace vrsph::detail
