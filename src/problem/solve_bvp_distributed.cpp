// SPDX-License-Identifier: BSD-3-Clause
// The boundary value problem over MPI ranks: the serial pipeline of solve_bvp.cpp on each
// rank's owned particles plus a halo, with every diagnostic reduced over the ranks.
//
//   chunk --(Morton partition, PetscSF)--> owned + halo --> neighbours --> owned stencil rows
//   --> owned rows of the system (global columns) --> PETSc MPIAIJ + KSP --> u back to the chunk
//
// Every stage that can fail on one rank runs in `collective`, so a failure anywhere is the
// same typed exception on every rank (no rank waits in a collective the others left).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <functional>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/parallel/distributed_cloud.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include "outward_normals.hpp"
#include "solve_bvp_distributed.hpp"
#include "transmissibilities.hpp"

namespace vrsph::detail {

namespace {
void check_size(const Field& v, Index n, const char* name, bool required) {
  if (v.size() == 0 && !required) return;
  check<InputError>(v.size() == n, "boundary value problem: ", name, " has ", v.size(), " values for ", n,
                    " particles of this rank's part of the cloud (size mismatch)");
}

std::vector<char> owned_mask(const DistributedCloud& dc, std::initializer_list<Tag> tags) {
  std::vector<char> m = tag_mask(dc.local, tags);
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = m[i] && dc.owned[i];
  return m;
}

// Infeasible rows of this rank, named by global id, and the counts over every rank; every
// rank gets the whole list, worst first (as serial).
void report_infeasible(const DistributedCloud& dc, const LocalResidualSummary& local, const char* what,
                       const BvpSolveOptions& o, BvpSolution& s) {
  const Communicator& comm = dc.comm;
  s.max_local_residual = std::max(s.max_local_residual, max_over_ranks(comm, local.max_relative));
  const long long count = sum_over_ranks(comm, static_cast<long long>(local.infeasible));
  s.infeasible += static_cast<Index>(count);
  if (count == 0) return;
  std::vector<double> mine;  // (residual, global id) pairs; ids are exact in a double below 2^53
  for (const auto& [residual, i] : local.worst) {
    mine.push_back(residual);
    mine.push_back(static_cast<double>(dc.global_id[static_cast<std::size_t>(i)]));
  }
  const std::vector<double> all = gather_over_ranks(comm, mine);
  std::vector<std::pair<Real, Index>> rows;
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) rows.emplace_back(all[k], static_cast<Index>(all[k + 1]));
  std::stable_sort(rows.begin(), rows.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (const auto& [residual, id] : rows) {
    s.infeasible_particles.push_back(id);
    s.infeasible_residuals.push_back(residual);
  }
  const Real worst = rows.empty() ? std::numeric_limits<Real>::quiet_NaN() : rows[0].first;
  const long long worst_id = rows.empty() ? -1 : rows[0].second;
  const std::string msg = infeasible_rows_warning(o.label.empty() ? o.method : o.label, count, what, worst, worst_id,
                                                  o.infeasible_tolerance);
  if (o.on_infeasible == InfeasiblePolicy::Error) throw NumericalError(msg);
  s.warnings.push_back(msg);
}

// Rows with columns renumbered from local dofs to global ones (sorted again: the halo dofs'
// global numbers need not follow the local order).
CsrMatrix globalise(const LinearSystem& sys, const std::vector<Index>& global_dof_of_particle, Index global_unknowns) {
  const Index m = sys.rows_owned;
  CsrMatrix A(m, global_unknowns);
  A.resizeNonZeros(sys.A.nonZeros());
  std::copy(sys.A.outerIndexPtr(), sys.A.outerIndexPtr() + m + 1, A.outerIndexPtr());
  std::vector<std::pair<Index, Real>> row;
  for (Index d = 0; d < m; ++d) {
    row.clear();
    for (Index k = sys.A.outerIndexPtr()[d]; k < sys.A.outerIndexPtr()[d + 1]; ++k) {
      const Index j = sys.particle_of_dof[static_cast<std::size_t>(sys.A.innerIndexPtr()[k])];
      row.emplace_back(global_dof_of_particle[static_cast<std::size_t>(j)], sys.A.valuePtr()[k]);
    }
    std::sort(row.begin(), row.end());
    Index out = sys.A.outerIndexPtr()[d];
    for (const auto& [c, v] : row) {
      A.innerIndexPtr()[out] = c;
      A.valuePtr()[out++] = v;
    }
  }
  return A;
}

// A message from code that ran on the local cloud names local particle numbers: reworded
// with the global numbers the user knows.
std::string with_global_numbers(const std::string& message, const DistributedCloud& dc) {
  return renumber_particles(message, [&](long long local) {
    return local < dc.local_size() ? static_cast<long long>(dc.global_id[static_cast<std::size_t>(local)]) : local;
  });
}

// A stage on the local cloud: collective, and its errors name global particle numbers.
void local_stage(const DistributedCloud& dc, const std::function<void()>& stage) {
  collective(dc.comm, [&] {
    try {
      stage();
    } catch (const std::exception& e) {
      rethrow_with_message(e, with_global_numbers(e.what(), dc));
    }
  });
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

BvpSolution solve_distributed(const BoundaryValueProblem& p, const BvpSolveOptions& o) {
  const Communicator& comm = o.communicator;
  const Index n_chunk = p.cloud.size();
  BvpSolution s;
  s.distribution.ranks = comm.size();
  const bool tensor = any_rank(comm, p.mobility.size() > 0);
  collective(comm, [&] {
    fault_point(comm, "distribute");
    check_size(p.a, n_chunk, "a", false);
    check_size(p.f, n_chunk, "f", true);
    check_size(p.g, n_chunk, "g", true);
    check_size(p.robin, n_chunk, "robin", false);
    check<InputError>(p.q.size() == 0 || p.q.size() == n_chunk, "boundary value problem: q has ", p.q.size(),
                      " values for ", n_chunk, " particles of this rank's part (size mismatch)");
    check<InputError>(p.mobility.size() == 0 || p.mobility.rows() == n_chunk, "boundary value problem: the mobility "
                      "has ", p.mobility.rows(), " rows for ", n_chunk, " particles (size mismatch)");
    check<InputError>(!tensor || p.a.size() == 0, "boundary value problem: give either a scalar coefficient a or a "
                      "tensor mobility, not both");
    check<ConfigError>(std::isfinite(o.infeasible_tolerance) && o.infeasible_tolerance > 0,
                       "infeasible tolerance must be positive and finite, got ", o.infeasible_tolerance);
    check<ConfigError>(std::isfinite(o.h) && o.h >= 0, "support radius h must be >= 0 (0: from the h-factor), got ", o.h);
    check<ConfigError>(o.h_knn >= 0, "h-knn (k of the k-th neighbour) must be >= 1, or 0 for the default 2d; got ",
                       o.h_knn);
    check<ConfigError>(std::isfinite(o.h_factor) && o.h_factor > 0, "h-factor must be positive and finite, got ", o.h_factor);
    check<ConfigError>(p.pinned < 0, "BoundaryValueProblem::pinned names a particle of one rank's part: with several "
                       "ranks use fix_constant");
    check<ConfigError>(!o.keep_matrices, "keep_matrices is not available for a distributed solve");
  });
  const bool with_a = any_rank(comm, p.a.size() > 0), with_grad_a = any_rank(comm, p.grad_a.size() > 0),
             with_q = any_rank(comm, p.q.size() > 0), with_robin = any_rank(comm, p.robin.size() > 0);
  // A field given on some ranks' parts must be on every part that reads it. The flux data q
  // and β are read only at Neumann particles: a part without any (a file that lists its
  // Neumann particles last) may leave them empty and gets zeros. a, ∇a and the mobility are
  // read everywhere: absent on one non-empty part while given on another is an error.
  const Index chunk_neumann = p.cloud.count(Tag::Neumann);
  collective(comm, [&] {
    const auto needed = [&](bool given_somewhere, bool given_here, bool read_here, const char* what) {
      check<InputError>(!given_somewhere || given_here || !read_here, "boundary value problem: ", what,
                        " is given on other ranks' parts but not on this rank's part (", n_chunk, " particles, ",
                        chunk_neumann, " Neumann); give it on every part that reads it");
    };
    needed(with_a, p.a.size() > 0, n_chunk > 0, "the coefficient a");
    needed(with_grad_a, p.grad_a.size() > 0, n_chunk > 0, "grad a");
    needed(tensor, p.mobility.size() > 0, n_chunk > 0, "the mobility");
    needed(with_q || chunk_neumann > 0, p.q.size() > 0, chunk_neumann > 0, "the Neumann flux q");
    needed(with_robin, p.robin.size() > 0, chunk_neumann > 0, "the Robin coefficient");
  });
  const auto at_neumann = [&](const Field& v) { return v.size() ? v : Field(Field::Zero(n_chunk)); };
  const auto method = builtin_methods().create(o.method, o.method_options);
  const long long global_n = sum_over_ranks(comm, static_cast<long long>(n_chunk));
  Real dx = 0;
  // The serial estimate_spacing of the whole cloud (its spacing, the domain's density, or
  // the median k-th neighbour distance of a user's cloud).
  dx = o.spacing > 0 ? o.spacing : estimate_spacing_over_ranks(p.cloud, comm);
  s.spacing = dx;
  s.h = o.h > 0 ? o.h : o.h_factor * dx;
  const bool knn = o.h <= 0 && o.h_mode == SmoothingMode::Knn, covering = o.h <= 0 && o.h_mode == SmoothingMode::Covering;
  if (covering) {
    const int dim = static_cast<int>(max_over_ranks(comm, static_cast<double>(p.cloud.size() ? p.cloud.dim : 0)));
    collective(comm, [&] {
      check<ConfigError>(p.cloud.size() == 0 || p.cloud.domain.shape != Domain::Shape::None,
                         "--h-mode covering needs a known domain (box or ball) for the covering radius; a cloud "
                         "without one (e.g. read from a file) cannot use it: use fixed or knn");
      check<InputError>(global_n > dim, "the covering radius needs more than ", dim, " particles");
    });
  }

  // Partition with a halo as wide as the method's rows read: reach() supports (2 for D2 = D D
  // and for Shepard/Voronoi volumes of the neighbours, 3 for their VRSPH volumes).
  Stopwatch watch;
  const int reach = method->reach();
  DistributedCloud dc = distribute(p.cloud, reach * s.h * (1 + 1e-9), comm);
  // knn radii h_i = kappa r_k(i): exact on the owner when every particle within r_k(i) is
  // local, i.e. r_k <= the halo width; the halo must also hold reach x max h_i. Widen and
  // partition again until both hold (one round for clouds without large holes).
  // Covering: h = kappa max(dx, r_N), r_N exact from each rank's owned Voronoi cells when
  // the halo holds every particle within 2 r_N of the owned ones (covering_radius.hpp);
  // the halo must also hold reach x h. Widen and partition again until both hold.
  while (covering) {
    CoveringRadius mine;
    local_stage(dc, [&] { mine = covering_radius_of_owned(dc.local, dc.owned, dx); });
    const Real r = max_over_ranks(comm, mine.radius), h = o.h_factor * std::max(dx, r);
    const Real need = std::max(2 * r, reach * h) * (1 + 1e-9);
    if (need <= dc.halo_width) {
      s.covering_radius = r;
      s.h = h;
      break;
    }
    dc = distribute(p.cloud, std::max(need, 2 * dc.halo_width), comm);
  }
  std::vector<Real> radii;
  if (knn) {
    const int k = o.h_knn > 0 ? o.h_knn : 2 * std::max(dc.local.dim, 1);
    for (;;) {
      std::vector<Real> rk;
      local_stage(dc, [&] { rk = kth_neighbour_distance(dc.local, k); });
      Real local_max = 0;
      for (Index i = 0; i < dc.local_size(); ++i)
        if (dc.owned[static_cast<std::size_t>(i)]) local_max = std::max(local_max, rk[static_cast<std::size_t>(i)]);
      const Real r_max = max_over_ranks(comm, local_max);
      const Real need = std::max(r_max, reach * o.h_factor * r_max) * (1 + 1e-9);
      if (r_max <= dc.halo_width && need <= dc.halo_width) {
        for (Real& r : rk) r *= o.h_factor;
        radii = std::move(rk);
        break;
      }
      dc = distribute(p.cloud, std::max(need, 2 * dc.halo_width), comm);
    }
    Field r(dc.local_size());
    for (Index i = 0; i < r.size(); ++i) r[i] = radii[static_cast<std::size_t>(i)];
    update_halo(dc, r);  // the halo's radii are their owners' (exact) ones
    radii.assign(r.data(), r.data() + r.size());
    double sum = 0;  // h reported as the mean radius over every particle, as in serial
    for (Index i = 0; i < r.size(); ++i)
      if (dc.owned[static_cast<std::size_t>(i)]) sum += r[i];
    s.h = sum_over_ranks(comm, sum) / static_cast<Real>(dc.global_size);
  }
  const PointCloud& cloud = dc.local;
  const Index n = cloud.size();
  s.particles = dc.global_size;
  s.distribution.owned = dc.owned_count;
  s.distribution.halo = dc.stats.halo;
  s.distribution.halo_bytes = dc.stats.halo_bytes;
  s.distribution.halo_bytes_max = static_cast<long long>(max_over_ranks(comm, static_cast<double>(dc.stats.halo_bytes)));
  s.distribution.halo_bytes_total = sum_over_ranks(comm, dc.stats.halo_bytes);
  s.distribution.migration_bytes = dc.stats.migration_bytes;
  s.distribution.halo_messages = dc.stats.halo_messages;
  {
    Real extent2 = 0;
    Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
    for (Index i = 0; i < n; ++i)
      if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Ghost) {
        lo = lo.cwiseMin(cloud.positions[static_cast<std::size_t>(i)]);
        hi = hi.cwiseMax(cloud.positions[static_cast<std::size_t>(i)]);
      }
    for (int k = 0; k < 3; ++k) {
      const Real a = min_over_ranks(comm, lo[k]), b = max_over_ranks(comm, hi[k]);
      if (b >= a) extent2 += (b - a) * (b - a);
    }
    const Real h_max = radii.empty() ? s.h : max_over_ranks(comm, *std::max_element(radii.begin(), radii.end()));
    collective(comm, [&] { check_support_is_local(h_max, std::sqrt(extent2), o.h > 0 ? 0 : o.h_factor); });
  }
  // The data at the owned and halo particles.
  const Field ones = Field::Ones(n_chunk);
  const Field a = chunk_to_local(dc, with_a ? p.a : ones);
  const Field f = chunk_to_local(dc, p.f), g = chunk_to_local(dc, p.g);
  const Field q = with_q ? chunk_to_local(dc, at_neumann(p.q)) : Field();
  const Field robin = with_robin ? chunk_to_local(dc, at_neumann(p.robin)) : Field();
  const Eigen::MatrixXd mobility = tensor ? chunk_to_local(dc, p.mobility) : Eigen::MatrixXd();
  const Eigen::MatrixXd grad_a = with_grad_a && !tensor ? chunk_to_local(dc, p.grad_a) : Eigen::MatrixXd();
  collective(comm, [&] {
    for (Index i = 0; i < n; ++i) {
      check<InputError>(std::isfinite(a[i]) && a[i] > 0, "the coefficient a = ", a[i], " at particle ",
                        dc.global_id[static_cast<std::size_t>(i)], " must be positive and finite");
    }
  });

  // Partition, halos and the data's migration: one stage, timed apart from the search.
  s.distribution.seconds_distribute = max_over_ranks(comm, watch.seconds());
  watch.restart();

  const std::vector<char> interior = owned_mask(dc, {Tag::Interior}), flux = owned_mask(dc, {Tag::Neumann}),
                          unknown_all = unknown_mask(cloud), unknown = owned_mask(dc, {Tag::Interior, Tag::Neumann});
  s.neumann_particles = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(std::count(flux.begin(), flux.end(), 1))));
  collective(comm, [&] {
    check<InputError>(s.neumann_particles == 0 || with_q, "boundary value problem: Neumann particles need the flux q");
    check<ConfigError>(s.neumann_particles == 0 || method->balances_flux_rows(StencilUse::System) ||
                           method->info().supports(OperatorKind::Gradient),
                       "method ", o.method, " has no gradient stencil for Neumann rows");
  });
  // Balance rows (VRSPH flux=balance): the Neumann particles' rows come with the operator.
  const bool balance = s.neumann_particles > 0 && method->balances_flux_rows(StencilUse::System);
  const std::vector<char>& operator_rows = balance ? unknown : interior;

  // Neighbours of the local particles; only the owned rows must have some (halo particles at
  // the halo's edge are incomplete and are never rows).
  SearchParams sp;
  sp.radius = s.h;
  sp.radii = radii;
  sp.min_neighbours = 0;
  NeighbourList nl;
  local_stage(dc, [&] {
    fault_point(comm, "neighbours");
    nl = find_neighbours(cloud, sp);
    for (Index i = 0; i < n; ++i)
      if (dc.owned[static_cast<std::size_t>(i)] && cloud.tags[static_cast<std::size_t>(i)] != Tag::Ghost && nl.count(i) < 1) {
        const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
        throw GeometryError(concat("particle ", dc.global_id[static_cast<std::size_t>(i)], " at (", x[0], ", ", x[1],
                                   ", ", x[2], ") has 0 neighbours within radius ", s.h,
                                   " (need at least 1); increase the smoothing radius or check the cloud"));
      }
    detail::check_outward_normals(cloud, nl, dc.owned, [&](Index i) { return static_cast<long long>(dc.global_id[static_cast<std::size_t>(i)]); });
  });
  s.seconds_neighbours = max_over_ranks(comm, watch.seconds());
  // Peaks without the serial path's per-stage resets: what this rank held up to each stage.
  const auto peak = [&](std::size_t& slot) {
    if (o.measure_memory) slot = peak_resident_memory_bytes();
  };
  peak(s.stage_peak_bytes.neighbours);

  // Owned stencil rows.
  watch.restart();
  StencilRequest req;
  req.kind = OperatorKind::DivAGrad;
  req.use = StencilUse::System;
  req.coefficient = tensor ? nullptr : &a;
  req.mobility = tensor ? &mobility : nullptr;
  if (grad_a.size()) req.coefficient_gradient = &grad_a;
  req.rows = operator_rows;
  const Discretisation disc{cloud, nl, o.kernel, dx, dc.global_size, length_scale(cloud, comm)};
  Stencil L, G;
  local_stage(dc, [&] {
    fault_point(comm, "stencil");
    L = method->build(disc, req);
    if (s.neumann_particles > 0 && !balance) {
      StencilRequest greq;
      greq.kind = OperatorKind::Gradient;
      greq.use = StencilUse::System;
      greq.rows = flux;
      G = method->build(disc, greq);
    }
  });
  s.seconds_stencil = max_over_ranks(comm, watch.seconds());
  peak(s.stage_peak_bytes.stencil);
  {
    long long nsum = 0, count = 0;
    for (Index i = 0; i < n; ++i)
      if (unknown[static_cast<std::size_t>(i)]) {
        nsum += nl.count(i);
        ++count;
      }
    nsum = sum_over_ranks(comm, nsum);
    count = sum_over_ranks(comm, count);
    s.neighbours_mean = static_cast<Real>(nsum) / static_cast<Real>(std::max<long long>(count, 1));
  }
  nl = NeighbourList();

  // Diagnostics over every rank.
  collective(comm, [&] {
    const auto all = static_cast<std::size_t>(n);
    report_infeasible(dc, summarise_local_residuals(L, interior, o.infeasible_tolerance, all), "interior", o, s);
    if (s.neumann_particles > 0)
      report_infeasible(dc, summarise_local_residuals(balance ? L : G, flux, o.infeasible_tolerance, all),
                        balance ? "Neumann (balance)" : "Neumann", o, s);
  });
  Real condition = 0;
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (interior[si] && !L.condition.empty()) condition = std::max(condition, L.condition[si]);
    if (flux[si] && !G.condition.empty()) condition = std::max(condition, G.condition[si]);
  }
  s.condition_max = max_over_ranks(comm, condition);
  collective(comm, [&] {
    for (Index i = 0; i < n; ++i) {
      if (!operator_rows[static_cast<std::size_t>(i)]) continue;
      for (Index k = L.row_begin(i); k < L.row_end(i); ++k)
        if (!std::isfinite(L.values[0][static_cast<std::size_t>(k)])) {
          const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
          throw NumericalError(concat(o.label.empty() ? o.method : o.label, ": the stencil row of particle ",
                                      dc.global_id[static_cast<std::size_t>(i)], " (", x[0], ", ", x[1], ", ", x[2],
                                      ") is not finite: the coefficient or mobility (or 1/h^2) overflows; rescale the problem"));
        }
    }
  });
  {
    summarise_transmissibilities(L, operator_rows, s);  // this rank's rows, then over the ranks
    s.signed_rows = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(s.signed_rows)));
    const long long negative = s.negative_transmissibilities;
    const Real xi = max_over_ranks(comm, std::isnan(s.xi_max) ? -std::numeric_limits<Real>::infinity() : s.xi_max);
    s.negative_transmissibilities = static_cast<Index>(sum_over_ranks(comm, negative));
    for (Index& i : s.negative_rows) i = dc.global_id[static_cast<std::size_t>(i)];
    s.xi_max = std::isfinite(xi) ? xi : std::nan("");
    if (s.signed_rows > 0)
      s.warnings.push_back(signed_rows_warning(o.label.empty() ? o.method : o.label, s));
    else if (method->info().monotone && s.negative_transmissibilities > 0)
      s.warnings.push_back(concat(o.label.empty() ? o.method : o.label, ": ", s.negative_transmissibilities,
                                  " negative off-diagonal weight(s) in interior rows of a scheme meant to be monotone: "
                                  "the maximum principle does not hold there ([SPE] (92)/(93), xi_max = ", s.xi_max, ")"));
  }
  if (o.check_m_matrix) {
    // Rows: the owned interior rows (all owned unknowns without flux rows); columns: every
    // unknown, halo copies included; chains followed over the ranks.
    const bool flux_rows_apart = s.neumann_particles > 0 && !balance;
    const std::vector<char>& rows = flux_rows_apart ? interior : unknown;
    std::vector<char> columns = flux_rows_apart ? tag_mask(cloud, {Tag::Interior}) : unknown_all;
    const std::optional<Stencil> robin_rows = with_robin_diagonal(L, flux, robin);
    const MMatrixReport mm = check_m_matrix(robin_rows ? *robin_rows : L, columns, 1e-12, rows,
                                            [&](std::span<const Index> off, std::span<const Index> tgt, std::vector<char> seeds) {
                                              return reach_over_ranks(dc, off, tgt, std::move(seeds));
                                            });
    const bool z = all_ranks(comm, mm.z_matrix), dd = all_ranks(comm, mm.diagonally_dominant),
               chained = all_ranks(comm, mm.chained);
    s.m_matrix = z && dd && chained;
    const long long rows_total = sum_over_ranks(comm, static_cast<long long>(mm.rows));
    s.m_matrix_summary = s.m_matrix ? concat("-L is an M-matrix (", rows_total, " unknown rows on ", comm.size(),
                                             " ranks, weakly chained diagonally dominant)")
                                    : concat("-L is NOT an M-matrix:", z ? "" : " off-diagonal entries of the wrong sign;",
                                             dd ? "" : " rows not diagonally dominant;",
                                             chained ? "" : " rows not connected to a strictly dominant (boundary) row;",
                                             " (", comm.size(), " ranks)");
  }

  // This rank's rows of the system, with global columns.
  watch.restart();
  Index pinned = -1;
  if (p.fix_constant) {
    // The interior particle nearest the centre of the domain (or of the unknowns), over every
    // rank; ties by global id, as the serial search keeps the first.
    Vec3 centre = Vec3::Zero();
    if (cloud.domain.shape == Domain::Shape::Ball) centre = cloud.domain.centre;
    else if (cloud.domain.shape == Domain::Shape::Box) centre = 0.5 * (cloud.domain.lo + cloud.domain.hi);
    else {
      long long count = 0;
      for (Index i = 0; i < n; ++i)
        if (interior[static_cast<std::size_t>(i)]) {
          centre += cloud.positions[static_cast<std::size_t>(i)];
          ++count;
        }
      for (int k = 0; k < 3; ++k) centre[k] = sum_over_ranks(comm, centre[k]);
      centre /= static_cast<Real>(std::max<long long>(sum_over_ranks(comm, count), 1));
    }
    Real best = std::numeric_limits<Real>::infinity();
    Index best_i = -1;
    for (Index i = 0; i < n; ++i)
      if (interior[static_cast<std::size_t>(i)] && (cloud.positions[static_cast<std::size_t>(i)] - centre).norm() < best) {
        best = (cloud.positions[static_cast<std::size_t>(i)] - centre).norm();
        best_i = i;
      }
    const Real global_best = min_over_ranks(comm, best);
    const long long mine = best == global_best && best_i >= 0 ? dc.global_id[static_cast<std::size_t>(best_i)]
                                                              : std::numeric_limits<long long>::max();
    const long long chosen = static_cast<long long>(-max_over_ranks(comm, -static_cast<double>(mine)));
    if (best_i >= 0 && dc.global_id[static_cast<std::size_t>(best_i)] == chosen) pinned = best_i;
  }
  BoundaryRows bc;
  if (s.neumann_particles > 0) {
    bc.gradient = balance ? nullptr : &G;
    bc.coefficient = tensor ? nullptr : &a;
    bc.mobility = tensor ? &mobility : nullptr;
    bc.q = q;
    bc.robin = robin;
  }
  bc.pinned = pinned;
  const AssemblyScope scope{unknown};
  LinearSystem sys;
  local_stage(dc, [&] {
    fault_point(comm, "assemble");
    sys = assemble(L, cloud, unknown_all, f, g, &bc, &scope);
  });
  s.local_residual = L.residual.empty() ? Field::Zero(n) : Field(Eigen::Map<const Field>(L.residual.data(), n));
  L = Stencil();
  G = Stencil();
  const Index m = sys.rows_owned;
  const long long unknowns = sum_over_ranks(comm, static_cast<long long>(m));
  const Index first_dof = static_cast<Index>(offset_over_ranks(comm, m));
  std::vector<Index> global_dof(static_cast<std::size_t>(n), -1);
  for (Index d = 0; d < m; ++d) global_dof[static_cast<std::size_t>(sys.particle_of_dof[static_cast<std::size_t>(d)])] = first_dof + d;
  update_halo(dc, global_dof);
  // Some data anywhere, and every unknown connected to it (else the system is singular).
  {
    const long long known = sum_over_ranks(comm, static_cast<long long>(
        std::count_if(cloud.tags.begin(), cloud.tags.end(), [](Tag t) { return t == Tag::Dirichlet; })));
    const bool robin_rows = any_rank(comm, robin.size() > 0 && robin.maxCoeff() > 0);
    const bool pinned_any = any_rank(comm, pinned >= 0);
    collective(comm, [&] {
      check<InputError>(unknowns > 0, "the problem has no unknown (interior) particle");
      check<InputError>(known > 0 || pinned_any || robin_rows,
                        s.neumann_particles > 0 ? "only Neumann data and no Dirichlet particle: the solution is determined "
                                                  "only up to a constant (singular system); fix the constant (--fix-constant)"
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
    const std::vector<char> reached = reach_over_ranks(dc, offsets, targets, std::move(seeds));
    long long floating = 0, first = std::numeric_limits<long long>::max();
    for (Index d = 0; d < m; ++d) {
      const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
      if (!reached[static_cast<std::size_t>(i)]) {
        ++floating;
        first = std::min<long long>(first, dc.global_id[static_cast<std::size_t>(i)]);
      }
    }
    floating = sum_over_ranks(comm, floating);
    first = static_cast<long long>(-max_over_ranks(comm, -static_cast<double>(first)));
    collective(comm, [&] {
      check<GeometryError>(floating == 0, floating, " unknown particle(s) are not connected to any Dirichlet particle "
                           "(singular system); first: particle ", first);
    });
  }
  LinearSystem global;
  global.A = globalise(sys, global_dof, static_cast<Index>(unknowns));
  global.b = std::move(sys.b);
  global.particle_of_dof.assign(sys.particle_of_dof.begin(), sys.particle_of_dof.begin() + m);
  global.rows_owned = m;
  s.unknowns = static_cast<Index>(unknowns);
  s.nnz_per_row = static_cast<Real>(sum_over_ranks(comm, static_cast<long long>(global.A.nonZeros()))) /
                  static_cast<Real>(std::max<long long>(unknowns, 1));
  s.seconds_assemble = max_over_ranks(comm, watch.seconds());
  peak(s.stage_peak_bytes.assemble);

  // The solve over every rank.
  Eigen::VectorXd x;
  SolverOptions solver = o.solver;
  solver.communicator = comm;
  if (solver.dimension == 0) solver.dimension = cloud.dim;
  const auto t0 = std::chrono::steady_clock::now();
  // PETSc's own collectives run inside: a failure on one rank cannot be agreed on there.
  collective_or_abort(comm, [&] {
    fault_point(comm, "solve");
    s.solve = solve(global, x, solver);
  });
  s.seconds_solve = max_over_ranks(comm, seconds_since(t0));
  peak(s.stage_peak_bytes.solve);
  s.warnings.insert(s.warnings.end(), s.solve.warnings.begin(), s.solve.warnings.end());
  collective(comm, [&] {
    if (!s.solve.success)
      throw NumericalError(concat("solver ", s.solve.solver, " failed for ", o.label.empty() ? o.method : o.label, ": ",
                                  s.solve.message, " (relative residual ", s.solve.residual, ")"));
  });

  // The solution at the owned particles, back in the chunk's order.
  Field u = sys.known;
  for (Index d = 0; d < m; ++d) u[global.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
  s.u = local_to_chunk(dc, u);
  s.local_residual = local_to_chunk(dc, s.local_residual);
  if (s.neumann_particles > 0 && !any_rank(comm, cloud.count(Tag::Dirichlet) > 0) &&
      !any_rank(comm, robin.size() > 0 && robin.maxCoeff() > 0)) {
    const Real volume = std::pow(dx, cloud.dim), area = std::pow(dx, cloud.dim - 1);
    std::vector<double> sums(3, 0.0);  // source, flux, scale
    for (Index i = 0; i < n; ++i) {
      if (!dc.owned[static_cast<std::size_t>(i)]) continue;
      const Tag t = cloud.tags[static_cast<std::size_t>(i)];
      if (t == Tag::Interior || t == Tag::Neumann) {
        const Real v = t == Tag::Interior ? volume : 0.5 * volume;
        sums[0] += v * f[i];
        sums[2] += v * std::abs(f[i]);
      }
      if (t == Tag::Neumann) {
        sums[1] += area * q[i];
        sums[2] += area * std::abs(q[i]);
      }
    }
    sum_over_ranks(comm, sums);
    s.neumann_imbalance = std::abs(sums[1] - sums[0]) / std::max(sums[2], std::numeric_limits<Real>::min());
    if (s.neumann_imbalance > 0.2)
      s.warnings.push_back(concat("only Neumann data, and they do not balance the source: boundary flux ~ ", sums[1],
                                  " but integral of f ~ ", sums[0], "; a solution exists only if they are equal, so "
                                  "this one is not meaningful: check q and f"));
  }
  return s;
}

}  // namespace vrsph::detail
