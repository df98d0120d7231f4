// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/config.hpp>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph {

InfeasiblePolicy parse_infeasible_policy(const std::string& name) {
  check<ConfigError>(name == "warn" || name == "error", "--on-infeasible must be warn or error, got '", name, "'");
  return name == "warn" ? InfeasiblePolicy::Warn : InfeasiblePolicy::Error;
}

std::vector<char> tag_mask(const PointCloud& cloud, std::initializer_list<Tag> tags) {
  std::vector<char> mask(static_cast<std::size_t>(cloud.size()));
  for (std::size_t i = 0; i < mask.size(); ++i)
    mask[i] = std::find(tags.begin(), tags.end(), cloud.tags[i]) != tags.end();
  return mask;
}

BoundaryValueProblem part_of(const BoundaryValueProblem& p, Index b, Index e) {
  BoundaryValueProblem q;
  q.cloud = slice(p.cloud, b, e);  // checks the range
  const auto cut = [&](const Field& v) { return v.size() ? Field(v.segment(b, e - b)) : Field(); };
  const auto cut_rows = [&](const Eigen::MatrixXd& m) {
    return m.size() ? Eigen::MatrixXd(m.middleRows(b, e - b)) : Eigen::MatrixXd();
  };
  q.a = cut(p.a);
  q.f = cut(p.f);
  q.g = cut(p.g);
  q.q = cut(p.q);
  q.robin = cut(p.robin);
  q.mobility = cut_rows(p.mobility);
  q.grad_a = cut_rows(p.grad_a);
  q.pinned = p.pinned >= b && p.pinned < e ? p.pinned - b : -1;
  q.fix_constant = p.fix_constant;
  return q;
}

std::vector<char> unknown_mask(const PointCloud& cloud) { return tag_mask(cloud, {Tag::Interior, Tag::Neumann}); }

namespace {
// The support and the partition in the solution's report.
void record_support(const detail::Partition& part, const detail::Support& support, BvpSolution& s) {
  s.spacing = support.spacing;
  s.h = support.h;
  s.covering_radius = support.covering_radius;
  s.particles = part.global_size();
  const DistributionStats st = part.stats();
  const Communicator& comm = part.comm();
  s.distribution.owned = static_cast<Index>(std::count(part.owned().begin(), part.owned().end(), 1));
  s.distribution.halo = st.halo;
  s.distribution.halo_bytes = st.halo_bytes;
  s.distribution.halo_bytes_max = static_cast<long long>(max_over_ranks(comm, static_cast<double>(st.halo_bytes)));
  s.distribution.halo_bytes_total = sum_over_ranks(comm, st.halo_bytes);
  s.distribution.migration_bytes = st.migration_bytes;
  s.distribution.seconds_distribute = max_over_ranks(comm, st.seconds);
  s.distribution.halo_messages = st.halo_messages;
}
}  // namespace

// The stages (bvp_pipeline.hpp), the same for one rank and for many: in serial the partition
// is the whole cloud and every exchange between ranks is the identity.
BvpSolution solve(const BoundaryValueProblem& p, const BvpSolveOptions& o) {
  BvpSolution s;
  const detail::ProblemFields given = detail::check_problem(p, o);
  s.distribution.ranks = o.communicator.size();
  // Peak memory per stage: the peak since the last mark.
  const auto mark = [&](std::size_t* slot) {
    if (!o.measure_memory) return;
    if (slot) *slot = peak_resident_memory_bytes();
    reset_peak_resident_memory();
  };
  mark(nullptr);
  const auto method = builtin_methods().create(o.method, o.method_options);

  // Support radius and partition; the data at the local (owned and halo) particles; their
  // neighbours (all timed as the neighbour stage, the partition's share in `distribution`).
  Stopwatch watch;
  detail::Support support;
  const auto part = detail::choose_support(p.cloud, o, rows_reach(*method, StencilUse::System, given.grad_a), support);
  const detail::LocalData data = detail::local_data(*part, p, given);
  record_support(*part, support, s);
  const detail::RowMasks masks = detail::row_masks(*part);
  s.neumann_particles = static_cast<Index>(
      sum_over_ranks(o.communicator, static_cast<long long>(std::count(masks.flux.begin(), masks.flux.end(), 1))));
  NeighbourList nl = detail::find_local_neighbours(*part, support, masks);
  s.seconds_neighbours = max_over_ranks(o.communicator, watch.seconds());
  mark(&s.stage_peak_bytes.neighbours);
  check_interrupt();  // a stop asked for (Ctrl-C in Python) between stages

  watch.restart();
  const Discretisation disc = detail::local_discretisation(*part, nl, o.kernel, support.spacing);
  detail::OperatorRows rows = detail::build_operator_rows(*part, *method, disc, data, masks, s.neumann_particles > 0,
                                                          o.method, StencilUse::System);
  s.seconds_stencil = max_over_ranks(o.communicator, watch.seconds());
  s.neighbours_mean = detail::mean_neighbours(*part, nl, masks);
  nl = NeighbourList();  // not needed any more: its memory goes back before assembly and solve
  mark(&s.stage_peak_bytes.stencil);
  check_interrupt();

  const Index pinned = detail::pinned_particle(*part, masks, p, given);
  // A pinned unknown (fix_constant, or a fully periodic box) is known, like a Dirichlet particle:
  // the M-matrix test's chains may end at it (without it every pure-Neumann system read "not
  // connected to a strictly dominant row").
  detail::diagnose_rows(*part, *method, rows, masks, data, pinned, o, s);

  watch.restart();
  LinearSystem sys = detail::assemble_owned_rows(*part, rows, masks, data, pinned, given, s);
  // The stencils are in the system now: keep what the report needs and free them.
  if (o.keep_matrices) s.operator_rows = detail::kept_operator_rows(*part, rows.L);
  if (any_rank(o.communicator, !rows.L.wall_flux.empty()))  // balance rows (a rank may have no Neumann row)
    s.wall_flux = rows.L.wall_flux.empty() ? Field(Field::Zero(part->local_size()))
                                           : Field(Eigen::Map<const Field>(rows.L.wall_flux.data(), part->local_size()));
  s.local_residual = rows.L.residual.empty() ? Field::Zero(part->local_size())
                                             : Field(Eigen::Map<const Field>(rows.L.residual.data(), part->local_size()));
  const detail::PinnedRow dropped_row =
      given.periodic_without_boundary ? detail::pinned_row(rows.L, data, pinned) : detail::PinnedRow{};
  rows = detail::OperatorRows();
  s.seconds_assemble = max_over_ranks(o.communicator, watch.seconds());
  mark(&s.stage_peak_bytes.assemble);
  check_interrupt();

  Eigen::VectorXd x = detail::solve_system(*part, sys, o, s);
  if (given.periodic_without_boundary) detail::spread_periodic_defect(*part, sys, dropped_row, p.f, o, x, s);
  mark(&s.stage_peak_bytes.solve);
  detail::report_solution(*part, sys, x, data, support.spacing, s);
  if (given.periodic_without_boundary) {  // u up to a constant: the one with zero mean
    const Real mean = sum_over_ranks(o.communicator, s.u.sum()) /
                      static_cast<Real>(std::max<long long>(1, sum_over_ranks(o.communicator, static_cast<long long>(s.u.size()))));
    s.u.array() -= mean;
  }
  if (o.keep_matrices) s.system = std::move(sys);
  return s;
}

}  // namespace vrsph
