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
  return given;
}

}  // namespace vrsph::detail
