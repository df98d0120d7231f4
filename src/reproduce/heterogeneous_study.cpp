// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <vrsph/reproduce/heterogeneous_study.hpp>
#include <vrsph/cloud/box_faces.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/problem/boundary_value_problem.hpp>
#include <vrsph/problem/tpfa.hpp>

namespace vrsph {

using detail::concat;

bool is_heterogeneous_problem(const std::string& problem) {
  return problem == "spe-channel" || problem == "spe-lognormal" || problem == "spe10";
}

namespace {

constexpr Real monotone_tolerance = 1e-9;

void check_params(const HeterogeneousStudyParams& p) {
  check<ConfigError>(is_heterogeneous_problem(p.problem), "unknown heterogeneous problem '", p.problem,
                     "' (known: spe-channel, spe-lognormal, spe10)");
  check<ConfigError>(!p.methods.empty(), "heterogeneous study: no method given");
  for (const auto& m : p.methods)
    if (m != "tpfa") (void)builtin_methods().info(m);  // unknown names fail here, before any work
  check<ConfigError>(std::isfinite(p.support_factor) && p.support_factor > 0 && p.support_factor <= 50,
                     "heterogeneous study: support factor must be in (0, 50], got ", p.support_factor);
  const KrylovStudyOptions& k = p.krylov;
  for (const auto& pc : k.preconditioners)
    check<ConfigError>(pc == "none" || pc == "jacobi" || pc == "ilu" || pc == "amg", "unknown preconditioner '", pc,
                       "' for the Krylov study (known: none, jacobi, ilu, amg)");
  check<ConfigError>(k.restart >= 1 && k.restart <= 10000, "GMRES restart must be in 1..10000, got ", k.restart);
  check<ConfigError>(std::isfinite(k.rtol) && k.rtol > 0 && k.rtol < 1, "Krylov tolerance must be in (0, 1), got ",
                     k.rtol);
  check<ConfigError>(k.max_iterations >= 1, "Krylov iteration cap must be >= 1, got ", k.max_iterations);
  check<ConfigError>(k.preconditioners.empty() || !p.communicator.distributed(),
                     "the Krylov study of the heterogeneous problems runs on one rank (it solves each assembled "
                     "system again serially); drop the Krylov preconditioners or run without mpirun");
}

// Peak memory of one method's run per particle: the neighbour list, the stencil and the
// kept matrices (~60 bytes per neighbour) and ~1500 bytes for the cloud, fields, TPFA
// reference and the solver (an upper bound of the measured peaks: 3D 40^3 and support
// 2 dx, 0.26 GB; estimate 0.23 GB on top of the ~30 MB the process starts with).
double run_bytes(int dim, double cells, Real support_factor) {
  const double ball = dim == 2 ? 3.14159 * support_factor * support_factor : 4.18879 * std::pow(support_factor, 3);
  return cells * (1500 + 60 * ball);
}

PermeabilityField field_of(const HeterogeneousStudyParams& p) {
  if (p.field.k.size() == 0 && p.n >= 1)
    check_memory_estimate(run_bytes(p.dim, std::pow(static_cast<double>(p.n), p.dim), p.support_factor),
                          "heterogeneous study", "use fewer cells (--n) or a smaller support (--h-factor)");
  if (p.field.k.size() > 0) {
    validate(p.field);
    check<ConfigError>(p.field.dim == p.dim, "the permeability field is ", p.field.dim, "D but the study is ", p.dim, "D");
    return p.field;
  }
  check<ConfigError>(p.problem != "spe10", "spe10 needs a permeability file (the SPE10 data set is not shipped: "
                                           "give spe_perm.dat or any field in its layout)");
  return p.problem == "spe-channel" ? channel_permeability(p.dim, p.n, p.channel) : lognormal_permeability(p.dim, p.n, p.lognormal);
}

std::string petsc_options_for(const std::string& pc, const KrylovStudyOptions& k) {
  std::string o = concat("-ksp_type gmres -ksp_gmres_restart ", k.restart, " -ksp_pc_side right ");
  if (pc == "none") return o + "-pc_type none";
  if (pc == "jacobi") return o + "-pc_type jacobi";
  if (pc == "ilu") return o + "-pc_type ilu -pc_factor_levels 0";
  return o + "-pc_type hypre -pc_hypre_type boomeramg";  // with vrsph's tuned BoomerAMG settings
}

void krylov_runs(const std::string& method, const LinearSystem& sys, const HeterogeneousStudyParams& p,
                 std::vector<KrylovRun>& out) {
  const Real bnorm = sys.b.norm();
  for (const auto& pc : p.krylov.preconditioners) {
    KrylovRun r;
    r.method = method;
    r.preconditioner = pc;
    SolverOptions so;
    so.type = SolverType::Petsc;
    so.rtol = p.krylov.rtol;
    so.max_iterations = p.krylov.max_iterations;
    so.scale_rows = false;  // the system as assembled: the preconditioner alone makes the difference
    so.dimension = p.dim;
    so.petsc_options = petsc_options_for(pc, p.krylov);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.size());
    try {
      const SolveReport rep = solve(sys, x, so);
      r.iterations = rep.iterations;
      r.converged = rep.success;
      r.reason = rep.reason;
      r.residual = rep.residual;
      r.seconds = rep.seconds;
      for (Real h : rep.residual_history) r.history.push_back(bnorm > 0 ? h / bnorm : h);
    } catch (const NumericalError& e) {  // e.g. a zero pivot in ILU(0): a result of the study, not a failure of it
      r.reason = std::string("error: ") + e.what();
    }
    out.push_back(std::move(r));
  }
}

// The rate along the flow axis of a flux-form operator: every pair (I, J) of an interior
// row carries F = V_I L_IJ (u_I - u_J) from I to J (V_I = dx^d), counted half from each
// row when both are interior (the symmetrised flux of a non-symmetric scheme) and fully
// otherwise (boundary particles have no conservation row). The rate through the
// cross-section x_axis = c is the sum of the pair fluxes crossing it; `mean` is its
// average over c in [h, 1 - h] (h the support radius: cross-sections that no pair of a
// boundary particle crosses, where the rows are the interior scheme's), `spread` the
// relative range of the rates through the cross-sections between particle layers, from
// the inlet to the outlet (0 for a conservative scheme: TPFA).
struct CutFluxes {
  Real mean = 0, spread = 0;
};

// Distributed: each rank's L holds the rows it owned; the sums are completed over the ranks.
CutFluxes cut_fluxes(const PointCloud& cloud, const SparseMatrix& L, const Field& u, int axis, int n, Real h,
                     const Communicator& comm) {
  const Real dx = 1.0 / n, volume = std::pow(dx, cloud.dim);
  const Real a = std::min(h, 0.25), b = 1 - a;  // the averaging window (a quarter of the domain at least)
  // Cross-sections: between the inlet particles and the first layer (dx/4), between layers
  // (k dx), between the last layer and the outlet particles (1 - dx/4).
  std::vector<Real> at(static_cast<std::size_t>(n + 1)), rate(static_cast<std::size_t>(n + 1), 0.0);
  for (int k = 0; k <= n; ++k) at[static_cast<std::size_t>(k)] = k == 0 ? dx / 4 : k == n ? 1 - dx / 4 : k * dx;
  CutFluxes out;
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    const Real yi = cloud.positions[static_cast<std::size_t>(i)][axis];
    for (SparseMatrix::InnerIterator it(L, i); it; ++it) {
      const auto j = static_cast<std::size_t>(it.col());
      if (it.col() == i) continue;
      const Real share = cloud.tags[j] == Tag::Interior ? 0.5 : 1.0;
      const Real f = share * volume * it.value() * (u[i] - u[it.col()]);
      const Real yj = cloud.positions[j][axis];
      const Real lo = std::min(yi, yj), hi = std::max(yi, yj), sign = yj > yi ? 1 : -1;
      out.mean += sign * f * std::max<Real>(0, std::min(hi, b) - std::max(lo, a));
      for (std::size_t k = 0; k < at.size(); ++k)
        if (at[k] > lo && at[k] < hi) rate[k] += sign * f;
    }
  }
  if (comm.distributed()) {
    out.mean = sum_over_ranks(comm, out.mean);
    sum_over_ranks(comm, rate);
  }
  out.mean /= b - a;
  const auto [mn, mx] = std::minmax_element(rate.begin(), rate.end());
  out.spread = out.mean != 0 ? (*mx - *mn) / std::abs(out.mean) : std::nan("");
  return out;
}

}  // namespace

namespace {
// Layout B over the unit box, each particle with its cell's permeability; no flow through
// every face but the inlet and the outlet.
struct ParticleProblem {
  PointCloud cloud;
  Eigen::MatrixXd mobility;
  Field g, harmonic;
  std::vector<Index> cell;
};

ParticleProblem particle_problem(const PermeabilityField& field, const TpfaOptions& to) {
  const int dim = field.dim, n = field.n, axis = to.flow_axis;
  ParticleProblem pp;
  pp.cloud = cell_centred_lattice(Domain::unit_box(dim), n, true);
  std::array<bool, 6> no_flow{};
  for (int a = 0; a < dim; ++a)
    if (a != axis) no_flow[static_cast<std::size_t>(2 * a)] = no_flow[static_cast<std::size_t>(2 * a + 1)] = true;
  retag_neumann_faces(pp.cloud, no_flow, 1.0 / n);
  const Index N = pp.cloud.size();
  pp.mobility.resize(N, dim);
  pp.cell.resize(static_cast<std::size_t>(N));
  pp.g = Field::Zero(N);
  for (Index i = 0; i < N; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = pp.cloud.positions[si];
    pp.cell[si] = field.cell_of(x);
    pp.mobility.row(i) = field.k.row(pp.cell[si]);
    if (pp.cloud.tags[si] == Tag::Dirichlet) pp.g[i] = x[axis] < 0.5 ? to.p_in : to.p_out;
  }
  pp.harmonic.resize(N);
  for (Index i = 0; i < N; ++i) pp.harmonic[i] = dim / pp.mobility.row(i).cwiseInverse().sum();
  return pp;
}

// The TPFA reference itself as a row of the table.
HeterogeneousRun tpfa_run(const PermeabilityField& field, const TpfaSolution& ref, double seconds) {
  HeterogeneousRun run;
  run.method = "tpfa";
  run.coefficient = "tensor";
  run.particles = run.unknowns = field.cells();
  run.h = 1.0 / field.n;
  run.outlet_flux = ref.outlet_flux;
  run.flux_spread = std::abs(ref.inlet_flux - ref.outlet_flux) / std::abs(ref.outlet_flux);
  run.m_matrix = true;  // by construction: non-negative transmissibilities, Dirichlet-connected
  run.min_u = ref.pressure.minCoeff();
  run.max_u = ref.pressure.maxCoeff();
  run.solve = ref.solve;
  run.seconds = seconds;
  return run;
}

// solve() over o.communicator, each rank passing an equal slice of the particles; u comes
// back at every particle on every rank.
BvpSolution solve_on_ranks(const BoundaryValueProblem& whole, const BvpSolveOptions& o) {
  const Communicator& comm = o.communicator;
  if (!comm.distributed()) return solve(whole, o);
  const Index N = whole.cloud.size(), ranks = comm.size(), r = comm.rank();
  BvpSolution s = solve(part_of(whole, N * r / ranks, N * (r + 1) / ranks), o);
  const std::vector<double> mine(s.u.data(), s.u.data() + s.u.size());
  const std::vector<double> all = gather_over_ranks(comm, mine);
  s.u = Eigen::Map<const Field>(all.data(), static_cast<Index>(all.size()));
  return s;
}

// A method's solve on the particles: the permeability as a scalar (isotropic fields), a
// tensor (methods that take one) or its harmonic mean.
BvpSolution method_solve(const HeterogeneousStudyParams& params, const PermeabilityField& field,
                         const ParticleProblem& pp, const std::string& method, HeterogeneousRun& run) {
  BoundaryValueProblem bp;
  bp.cloud = pp.cloud;
  const Index N = pp.cloud.size();
  if (field.isotropic()) {  // exact as a scalar, and no tensor-only corrections (VRSPH's ∇m targets)
    bp.a = pp.mobility.col(0);
    run.coefficient = "scalar";
  } else if (builtin_methods().info(method).tensor_mobility) {
    bp.mobility = pp.mobility;
    run.coefficient = "tensor";
  } else {
    bp.a = pp.harmonic;
    run.coefficient = "harmonic";
  }
  bp.f = Field::Zero(N);
  bp.g = pp.g;
  bp.q = Field::Zero(N);
  BvpSolveOptions o;
  o.method = method;
  if (auto it = params.method_options.find(method); it != params.method_options.end()) o.method_options = it->second;
  o.kernel = params.kernel;
  o.h = params.support_factor * (1.0 / field.n);  // as the spacing dx = 1/n times the factor
  o.spacing = 1.0 / field.n;
  o.solver = params.solver;
  o.infeasible_tolerance = params.infeasible_tolerance;
  o.keep_matrices = true;
  o.label = concat(method, " ", params.problem);
  o.communicator = params.communicator;
  Stopwatch watch;
  BvpSolution s = solve_on_ranks(bp, o);
  run.seconds = watch.seconds();
  run.particles = s.particles;
  run.unknowns = s.unknowns;
  run.h = s.h;
  run.m_matrix = s.m_matrix;
  run.negative_transmissibilities = s.negative_transmissibilities;
  run.infeasible = s.infeasible;
  run.solve = s.solve;
  return s;
}

// Cell by cell against TPFA at the cell-centre particles, and the range of u.
void compare_with_tpfa(const ParticleProblem& pp, const Field& u, const Field& reference, HeterogeneousRun& run) {
  Real sum = 0;
  Index count = 0;
  run.min_u = std::numeric_limits<Real>::infinity();
  run.max_u = -run.min_u;
  for (Index i = 0; i < pp.cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (pp.cloud.tags[si] == Tag::Dirichlet) continue;
    run.min_u = std::min(run.min_u, u[i]);
    run.max_u = std::max(run.max_u, u[i]);
    if (pp.cloud.tags[si] != Tag::Interior) continue;
    const Real r = reference[pp.cell[si]], e = std::abs(u[i] - r);
    run.error_abs_max = std::max(run.error_abs_max, e);
    const Real rel = r != 0 ? e / std::abs(r) : std::numeric_limits<Real>::infinity();
    run.error_rel_max = std::max(run.error_rel_max, rel);
    sum += rel * rel;
    ++count;
  }
  run.error_rel_rms = count ? std::sqrt(sum / static_cast<Real>(count)) : std::nan("");
}
}  // namespace

HeterogeneousStudyResult run_heterogeneous_study(const HeterogeneousStudyParams& params) {
  check_params(params);
  HeterogeneousStudyResult res;
  res.params = params;
  const PermeabilityField field = field_of(params);
  res.params.field = field;
  res.params.n = field.n;
  const auto report = [&](const std::string& what, double f) {
    if (params.progress) params.progress(what, f);
  };
  const std::size_t stages = params.methods.size() * (1 + params.krylov.preconditioners.size());
  std::size_t stage = 0;

  // The reference: TPFA on the cells, solved directly when small (auto).
  TpfaOptions to;
  to.flow_axis = params.flow_axis;
  to.solver = params.solver;
  report("tpfa reference", 0);
  Stopwatch watch;
  const TpfaSolution ref = solve_tpfa(field, to);
  const double tpfa_seconds = watch.seconds();
  res.reference = ref.pressure;
  const ParticleProblem pp = particle_problem(field, to);
  if (params.keep_fields) res.cloud = pp.cloud;

  for (const auto& method : params.methods) {
    report(method, static_cast<double>(stage++) / static_cast<double>(stages));
    HeterogeneousRun run;
    run.method = method;
    if (method == "tpfa") {
      run = tpfa_run(field, ref, tpfa_seconds);
      if (!params.krylov.preconditioners.empty()) {
        report("tpfa krylov", static_cast<double>(stage) / static_cast<double>(stages));
        krylov_runs(method, assemble_tpfa(field, to), params, res.krylov);
      }
    } else {
      const BvpSolution s = method_solve(params, field, pp, method, run);
      res.warnings.insert(res.warnings.end(), s.warnings.begin(), s.warnings.end());
      compare_with_tpfa(pp, s.u, ref.pressure, run);
      const CutFluxes q = cut_fluxes(pp.cloud, s.operator_rows, s.u, params.flow_axis, field.n, s.h, params.communicator);
      run.outlet_flux = q.mean;
      run.flux_spread = q.spread;
      if (params.keep_fields) run.u = s.u;
      if (!params.krylov.preconditioners.empty()) {
        report(method + " krylov", static_cast<double>(stage) / static_cast<double>(stages));
        krylov_runs(method, s.system, params, res.krylov);
      }
    }
    stage += params.krylov.preconditioners.size();
    const Real lo = std::min(to.p_in, to.p_out), hi = std::max(to.p_in, to.p_out);
    const Real tol = monotone_tolerance * (hi - lo);
    run.monotone = run.min_u >= lo - tol && run.max_u <= hi + tol;
    run.flux_error_rel = std::abs(run.outlet_flux - ref.outlet_flux) / std::abs(ref.outlet_flux);
    res.runs.push_back(std::move(run));
  }
  report("done", 1);
  return res;
}

Table to_table(const HeterogeneousStudyResult& r) {
  Table t;
  t.columns = {"method", "coefficient", "particles", "unknowns", "error_rel_vs_tpfa", "error_rms_rel_vs_tpfa",
               "error_abs_vs_tpfa", "outlet_flux", "flux_spread", "flux_error_vs_tpfa", "mmatrix",
               "negative_transmissibilities", "min_u", "max_u", "monotone", "infeasible", "solver", "solver_iterations",
               "seconds"};
  for (const auto& x : r.runs)
    t.add_row({{"method", x.method}, {"coefficient", x.coefficient}, {"particles", static_cast<long long>(x.particles)},
               {"unknowns", static_cast<long long>(x.unknowns)}, {"error_rel_vs_tpfa", x.error_rel_max},
               {"error_rms_rel_vs_tpfa", x.error_rel_rms}, {"error_abs_vs_tpfa", x.error_abs_max},
               {"outlet_flux", x.outlet_flux}, {"flux_spread", x.flux_spread}, {"flux_error_vs_tpfa", x.flux_error_rel},
               {"mmatrix", x.m_matrix}, {"negative_transmissibilities", static_cast<long long>(x.negative_transmissibilities)},
               {"min_u", x.min_u}, {"max_u", x.max_u}, {"monotone", x.monotone},
               {"infeasible", static_cast<long long>(x.infeasible)}, {"solver", x.solve.solver},
               {"solver_iterations", static_cast<long long>(x.solve.iterations)}, {"seconds", x.seconds}});
  return t;
}

Table krylov_table(const HeterogeneousStudyResult& r) {
  Table t;
  t.columns = {"method", "preconditioner", "iterations", "converged", "residual", "reason", "seconds"};
  for (const auto& k : r.krylov)
    t.add_row({{"method", k.method}, {"preconditioner", k.preconditioner}, {"iterations", static_cast<long long>(k.iterations)},
               {"converged", k.converged}, {"residual", k.residual}, {"reason", k.reason}, {"seconds", k.seconds}});
  return t;
}

Table krylov_history_table(const HeterogeneousStudyResult& r) {
  Table t;
  t.columns = {"method", "preconditioner", "iteration", "residual"};
  for (const auto& k : r.krylov)
    for (std::size_t i = 0; i < k.history.size(); ++i)
      t.add_row({{"method", k.method}, {"preconditioner", k.preconditioner}, {"iteration", static_cast<long long>(i)},
                 {"residual", k.history[i]}});
  return t;
}

Json metadata_json(const HeterogeneousStudyResult& r) {
  const auto& p = r.params;
  const auto& f = p.field;
  Json j;
  j["problem"] = p.problem;
  j["substitute_for_spe10"] = p.problem != "spe10";
  j["dim"] = p.dim;
  j["cells_per_axis"] = f.n;
  j["cells"] = f.cells();
  j["k_min"] = f.k.minCoeff();
  j["k_max"] = f.k.maxCoeff();
  j["contrast"] = f.contrast();
  j["isotropic"] = f.isotropic();
  if (p.problem == "spe-channel") {
    j["channels"] = p.channel.channels > 0 ? p.channel.channels : (p.dim == 2 ? 4 : 8);
    j["seed"] = p.channel.seed;
  } else if (p.problem == "spe-lognormal") {
    j["sigma_ln"] = p.lognormal.sigma_ln;
    j["correlation_length"] = p.lognormal.correlation_length;
    j["seed"] = p.lognormal.seed;
  }
  j["flow_axis"] = std::string(1, "xyz"[p.flow_axis]);
  j["boundary"] = "u = 1 at the inlet face, 0 at the outlet face, no flow elsewhere";
  j["kernel"] = std::string(kernel_info(p.kernel).name);
  j["support_factor"] = p.support_factor;
  j["solver"] = to_string(p.solver.type);
  TpfaOptions to;
  to.flow_axis = p.flow_axis;
  j["tpfa_outlet_flux"] = r.reference.size() ? tpfa_boundary_flux(f, r.reference, to, true) : 0.0;
  if (!p.krylov.preconditioners.empty()) {
    Json k;
    k["ksp"] = "gmres";
    k["restart"] = p.krylov.restart;
    k["rtol"] = p.krylov.rtol;
    k["max_iterations"] = p.krylov.max_iterations;
    k["side"] = "right (true residual)";
    k["scaled_rows"] = false;
    k["initial_guess"] = "zero";
    k["preconditioners"] = p.krylov.preconditioners;
    j["krylov"] = k;
  }
  j["warnings"] = r.warnings;
  return j;
}

}  // namespace vrsph
