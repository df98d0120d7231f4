// SPDX-License-Identifier: BSD-3-Clause
// `vrsph bench update`: particles advected by a divergence-free cellular flow for K steps; per
// step the update path (vrsph::Operators: Verlet skin, storage reused, VRSPH's NNLS warm start)
// against a fresh build (search + stencils from nothing) on the same positions, in the same
// run: seconds per step for the neighbours, the stencils (Laplacian and gradient) and the
// divergence of the velocity (applied from the gradient stencil in both), their ratio, the
// warm-start hit rate, and the operators' errors of both paths on the same fields.
#include <cmath>
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/moving/operators.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vrsph::cli {

namespace {
constexpr double pi = 3.14159265358979323846;

struct UpdateArgs {
  int dim = 2, n = 1000, steps = 10, threads = 0;
  double h_factor = 3, move = 0.1, skin = 0.2;
  std::string method = "vrsph";
  std::vector<std::string> method_opts;
  bool warm_start = true;
  bool share_volumes = true;
  std::string periodic;  // periodic axes ("x,y", "all"; empty: none)
  bool div_a_grad = false;
  std::uint64_t seed = 1;
  OutputOptions out;
};

// Per axis the wave number of the flow and of the test field: 2π along a periodic axis (one
// period of the box), π across walls (the sine vanishes on both faces).
Vec3 wave_numbers(const PointCloud& c) {
  Vec3 w = Vec3::Constant(pi);
  for (int k = 0; k < c.dim; ++k)
    if (c.domain.periodic[static_cast<std::size_t>(k)]) w[k] = 2 * pi;
  return w;
}

// A cellular flow of the unit box, periodic along its periodic axes: divergence-free, its normal
// component zero on every wall (particles stay inside), |u| <= 1 in 2D and <= 2 in 3D. With
// walls only it is (sin πx cos πy, -cos πx sin πy) and its 3D analogue.
Vec3 cellular_velocity(const Vec3& x, const PointCloud& c) {
  const Vec3 w = wave_numbers(c);
  const Real sx = std::sin(w[0] * x[0]), cx = std::cos(w[0] * x[0]), sy = std::sin(w[1] * x[1]), cy = std::cos(w[1] * x[1]);
  if (c.dim == 1) return {0.3 * sx, 0, 0};  // 1D: not divergence-free (nothing is but a constant)
  // Amplitudes A_k with Σ_k A_k w_k = 0: the divergence (Σ_k A_k w_k) Π cos vanishes.
  if (c.dim == 2) return {pi / w[0] * sx * cy, -pi / w[1] * cx * sy, 0};
  const Real sz = std::sin(w[2] * x[2]), cz = std::cos(w[2] * x[2]);
  return {2 * pi / w[0] * sx * cy * cz, -pi / w[1] * cx * sy * cz, -pi / w[2] * cx * cy * sz};
}

// The Taylor–Green field of the fully periodic unit box (2D; 3D: its first two components), |u| <= 1.
Vec3 taylor_green_velocity(const Vec3& x, int dim) {
  const Real u = -std::cos(2 * pi * x[0]) * std::sin(2 * pi * x[1]), v = std::sin(2 * pi * x[0]) * std::cos(2 * pi * x[1]);
  return dim == 1 ? Vec3(0.3 * std::sin(2 * pi * x[0]), 0, 0) : Vec3(u, v, 0);
}

Vec3 flow_velocity(const Vec3& x, const PointCloud& c) {
  return c.domain.fully_periodic() ? taylor_green_velocity(x, c.dim) : cellular_velocity(x, c);
}

// Midpoint (RK2) step of the interior particles (boundary particles stay), wrapped into a
// periodic box.
void advect(std::vector<Vec3>& x, const PointCloud& c, Real dt) {
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (c.tags[si] != Tag::Interior) continue;
    const Vec3 mid = x[si] + 0.5 * dt * flow_velocity(x[si], c);
    x[si] = c.domain.wrap(x[si] + dt * flow_velocity(mid, c));
  }
}

struct Errors {
  double laplacian = 0, divergence = 0, div_a_grad = std::nan("");
};

// The test field f = Π sin(w_k x_k) (wave_numbers: zero on the walls, periodic along the
// periodic axes), its gradient, and its Laplacian -|w|² f.
Real product_of_sines(const Vec3& x, const PointCloud& c, Vec3* gradient = nullptr) {
  const Vec3 w = wave_numbers(c);
  Real f = 1;
  for (int k = 0; k < c.dim; ++k) f *= std::sin(w[k] * x[k]);
  if (gradient) {
    *gradient = Vec3::Zero();
    for (int k = 0; k < c.dim; ++k) {
      Real g = w[k] * std::cos(w[k] * x[k]);
      for (int j = 0; j < c.dim; ++j)
        if (j != k) g *= std::sin(w[j] * x[j]);
      (*gradient)[k] = g;
    }
  }
  return f;
}

Real test_laplacian_factor(const PointCloud& c) {
  const Vec3 w = wave_numbers(c);
  Real sum = 0;
  for (int k = 0; k < c.dim; ++k) sum += w[k] * w[k];
  return sum;
}

// --div-a-grad's coefficient at the particles' places: a = 1 + f / 2 with f = Π sin(w x_k).
Field bench_coefficient(const std::vector<Vec3>& x, const PointCloud& c) {
  Field a(static_cast<Index>(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i) a[static_cast<Index>(i)] = 1 + 0.5 * product_of_sines(x[i], c);
  return a;
}

// Max error of div(a grad f) over the interior rows that meet their moments, for a = 1 + f/2:
// grad a . grad f + a lap f = |grad f|^2 / 2 - |w|^2 f a.
double div_a_grad_error(const PointCloud& c, const Stencil& s) {
  const Real w2 = test_laplacian_factor(c);
  Field f(c.size());
  for (Index i = 0; i < c.size(); ++i) f[i] = product_of_sines(c.positions[static_cast<std::size_t>(i)], c);
  const Eigen::MatrixXd A = apply(s, f);
  double e = 0;
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (c.tags[si] != Tag::Interior || (!s.residual.empty() && s.residual[si] > 1e-8)) continue;
    Vec3 g;
    product_of_sines(c.positions[si], c, &g);
    const Real exact = 0.5 * g.squaredNorm() - w2 * f[i] * (1 + 0.5 * f[i]);
    e = std::max(e, std::abs(A(i, 0) - exact));
  }
  return e;
}

// Max errors over the interior rows whose moment conditions hold: the Laplacian of
// prod sin(w_k x_k) and the divergence of the flow (0).
Errors operator_errors(const PointCloud& c, const Stencil& lap, const Stencil& grad) {
  Field f(c.size());
  Eigen::MatrixXd U(c.size(), c.dim);
  for (Index i = 0; i < c.size(); ++i) {
    const Vec3& x = c.positions[static_cast<std::size_t>(i)];
    f[i] = product_of_sines(x, c);
    const Vec3 u = flow_velocity(x, c);
    for (int k = 0; k < c.dim; ++k) U(i, k) = u[k];
  }
  const Eigen::MatrixXd L = apply(lap, f), D = apply_vector(VectorOperator::Divergence, grad, U);
  Errors e;
  const Real w2 = test_laplacian_factor(c);
  if (c.dim == 1) e.divergence = std::nan("");  // no divergence-free flow in 1D: not measured
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (c.tags[si] != Tag::Interior || (!lap.residual.empty() && lap.residual[si] > 1e-8)) continue;
    e.laplacian = std::max(e.laplacian, std::abs(L(i, 0) + w2 * f[i]));
    if (c.dim > 1 && (grad.residual.empty() || grad.residual[si] <= 1e-8)) e.divergence = std::max(e.divergence, std::abs(D(i, 0)));
  }
  return e;
}

long long threads_in_use() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

struct PathTimes {
  double neighbours = 0, stencils = 0, divergence = 0;
  double total() const { return neighbours + stencils + divergence; }
};

// What the K steps measured: per-path seconds, warm-start counts, the last step's errors.
struct UpdateRun {
  PathTimes update, fresh;
  Index hits = 0, warm_rows = 0, searches = 0, particles = 0;
  Index borrowed = 0, first_derivative_rows = 0;  // gradient (and div(a grad)) rows that took the Laplacian's volumes, of all
  Errors e_update, e_fresh;
  double first_build = 0;
};

void check_update_args(const UpdateArgs& a) {
  check<ConfigError>(a.dim >= 1 && a.dim <= 3, "--dim must be 1, 2 or 3");
  check<ConfigError>(a.n >= 4 && a.n <= 100000, "--n must be in [4, 100000]");
  check<ConfigError>(a.steps >= 1 && a.steps <= 100000, "--steps must be in [1, 100000]");
  check<ConfigError>(std::isfinite(a.move) && a.move > 0 && a.move <= 1, "--move (the largest displacement per step in dx) must be in (0, 1]");
  check<ConfigError>(std::pow(a.n + 1.0, a.dim) * a.steps <= 1e10, "--n ", a.n, " and --steps ", a.steps, ": over 1e10 particle updates (hours)");
}

// Each step: the particles advected, the update path (Operators::update), then a fresh build
// (search + stencils) on the same positions; the divergence of the flow applied in both.
UpdateRun run_steps(const UpdateArgs& a) {
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(a.dim);
  spec.box.set_periodic(a.periodic);
  spec.n = a.n;
  spec.seed = a.seed;
  const StudyCloud sc = make_study_cloud(spec);
  // The largest speed is 1 (2 in 3D but on the fully periodic box's Taylor–Green field).
  const Real dt = a.move * sc.dx / (a.dim == 3 && !sc.cloud.domain.fully_periodic() ? 2.0 : 1.0);
  OperatorsOptions o;
  o.method = a.method;
  if (auto per_method = parse_method_options(a.method_opts, {a.method}); per_method.contains(a.method))
    o.method_options = per_method.at(a.method);
  o.h_factor = a.h_factor;
  o.skin = a.skin;
  o.warm_start = a.warm_start;
  o.share_volumes = a.share_volumes;
  if (a.div_a_grad) {
    o.operators.push_back(OperatorKind::DivAGrad);
    o.coefficient = bench_coefficient(sc.cloud.positions, sc.cloud);
  }
  UpdateRun run;
  run.particles = sc.cloud.size();
  Stopwatch build_watch;
  Operators ops(sc.cloud, o);
  run.first_build = build_watch.seconds();
  const auto method = builtin_methods().create(a.method, o.method_options);
  PointCloud fresh_cloud = sc.cloud;
  std::vector<Vec3> x = sc.cloud.positions;
  Progress progress;
  for (int step = 0; step < a.steps; ++step) {
    progress.update("step " + std::to_string(step + 1) + "/" + std::to_string(a.steps), static_cast<double>(step) / a.steps);
    advect(x, sc.cloud, dt);
    Field coefficient;  // --div-a-grad: a at the new places, given with them
    if (a.div_a_grad) {
      coefficient = bench_coefficient(x, sc.cloud);
      ops.update(x, coefficient);
    } else {
      ops.update(x);
    }
    run.update.neighbours += ops.stats().seconds_neighbours;
    run.update.stencils += ops.stats().seconds_stencils;
    run.hits += ops.stats().warm_hits;
    run.warm_rows += ops.stats().warm_rows;
    run.borrowed += ops.stats().borrowed_rows;
    run.first_derivative_rows += ops.cloud().size() * (a.div_a_grad ? 2 : 1);  // the rows that may borrow
    Eigen::MatrixXd U(sc.cloud.size(), a.dim);
    for (Index i = 0; i < sc.cloud.size(); ++i) U.row(i) = flow_velocity(x[static_cast<std::size_t>(i)], sc.cloud).head(a.dim).transpose();
    Stopwatch w;
    if (a.dim > 1) (void)ops.apply(VectorOperator::Divergence, U);
    run.update.divergence += w.seconds();
    fresh_cloud.positions = x;
    w.restart();
    SearchParams sp;
    sp.radius = ops.radius();
    const NeighbourList nl = find_neighbours(fresh_cloud, sp);
    run.fresh.neighbours += w.seconds();
    w.restart();
    // A periodic box: the minimum-image list as it is where the method reads pair vectors, else
    // the images (what a user without the update path would run).
    const Discretisation disc{fresh_cloud, nl, KernelType::CubicSpline, ops.spacing()};
    auto fresh_build_with = [&](const StencilRequest& req) {
      return nl.shifts.empty() || method->reads_periodic_pairs(req)
                 ? method->build(disc, req)
                 : periodic_stencil(*method, fresh_cloud, sp, KernelType::CubicSpline, ops.spacing(), req);
    };
    auto fresh_build = [&](OperatorKind kind) { return fresh_build_with(StencilRequest{kind}); };
    const Stencil lap = fresh_build(OperatorKind::Laplacian);
    const Stencil grad = fresh_build(OperatorKind::Gradient);
    Stencil div_a_grad;
    if (a.div_a_grad) div_a_grad = fresh_build_with(StencilRequest{OperatorKind::DivAGrad, &coefficient});
    run.fresh.stencils += w.seconds();
    w.restart();
    if (a.dim > 1) (void)apply_vector(VectorOperator::Divergence, grad, U);
    run.fresh.divergence += w.seconds();
    if (step + 1 == a.steps) {
      run.e_update = operator_errors(ops.cloud(), ops.stencil(OperatorKind::Laplacian), ops.stencil(OperatorKind::Gradient));
      run.e_fresh = operator_errors(fresh_cloud, lap, grad);
      if (a.div_a_grad) {
        run.e_update.div_a_grad = div_a_grad_error(ops.cloud(), ops.stencil(OperatorKind::DivAGrad));
        run.e_fresh.div_a_grad = div_a_grad_error(fresh_cloud, div_a_grad);
      }
    }
  }
  run.searches = ops.stats().searches - 1;  // the construction's not counted
  return run;
}

void run_update_bench(const UpdateArgs& a) {
  check_update_args(a);
  set_thread_count(a.threads);
  const UpdateRun run = run_steps(a);
  Table t;
  t.columns = {"stage", "dim", "particles", "threads", "steps", "seconds_per_step", "seconds_fresh_per_step",
               "ratio_to_fresh", "searches", "warm_start_hit_rate", "borrowed_volume_rate", "laplacian_error", "laplacian_error_fresh",
               "divergence_error", "divergence_error_fresh"};
  if (a.div_a_grad) {
    t.columns.push_back("div_a_grad_error");
    t.columns.push_back("div_a_grad_error_fresh");
  }
  const double hit_rate = run.warm_rows > 0 ? static_cast<double>(run.hits) / static_cast<double>(run.warm_rows) : 0.0;
  const double borrow_rate =
      run.first_derivative_rows > 0 ? static_cast<double>(run.borrowed) / static_cast<double>(run.first_derivative_rows) : 0.0;
  auto row = [&](const std::string& stage, double u, double f) {
    std::vector<std::pair<std::string, TableCell>> cells{
        {"stage", stage}, {"dim", static_cast<long long>(a.dim)}, {"particles", static_cast<long long>(run.particles)},
        {"threads", threads_in_use()}, {"steps", static_cast<long long>(a.steps)},
        {"seconds_per_step", u / a.steps}, {"seconds_fresh_per_step", f / a.steps}, {"ratio_to_fresh", u / f},
        {"searches", static_cast<long long>(run.searches)}, {"warm_start_hit_rate", hit_rate},
        {"borrowed_volume_rate", borrow_rate},
        {"laplacian_error", run.e_update.laplacian}, {"laplacian_error_fresh", run.e_fresh.laplacian},
        {"divergence_error", run.e_update.divergence}, {"divergence_error_fresh", run.e_fresh.divergence}};
    if (a.div_a_grad) {
      cells.emplace_back("div_a_grad_error", run.e_update.div_a_grad);
      cells.emplace_back("div_a_grad_error_fresh", run.e_fresh.div_a_grad);
    }
    t.add_row(cells);
  };
  row("neighbours", run.update.neighbours, run.fresh.neighbours);
  row(a.div_a_grad ? "stencils (laplacian + gradient + div-a-grad)" : "stencils (laplacian + gradient)", run.update.stencils,
      run.fresh.stencils);
  row("divergence (apply)", run.update.divergence, run.fresh.divergence);
  row("total", run.update.total(), run.fresh.total());
  Json extra;
  extra["benchmark"] = "update";
  extra["method"] = a.method;
  std::string options;
  for (const auto& item : a.method_opts) options += (options.empty() ? "" : " ") + item;
  extra["method_options"] = options;
  extra["h_factor"] = a.h_factor;
  extra["move_per_step_dx"] = a.move;
  extra["skin_fraction"] = a.skin;
  extra["warm_start"] = a.warm_start;
  extra["share_volumes"] = a.share_volumes;
  Domain box = Domain::unit_box(a.dim);
  box.set_periodic(a.periodic);
  extra["periodic"] = box.any_periodic();
  extra["periodic_axes"] = box.periodic_axes();
  extra["div_a_grad"] = a.div_a_grad;
  extra["first_build_seconds"] = run.first_build;
  extra["peak_memory_mib"] = peak_memory_mib();
  emit(t, a.out, extra, "", "", "", "");
}
}  // namespace

void add_update_bench(CLI::App& bench) {
  auto a = std::make_shared<UpdateArgs>();
  auto* cmd = bench.add_subcommand("update", "Moving particles: per-step update of the Laplacian, gradient and divergence "
                                             "(Verlet skin, warm-started NNLS) against a fresh build in the same run");
  cmd->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction of the perturbed unit lattice ((n+1)^d particles)")->capture_default_str();
  cmd->add_option("--steps", a->steps, "Time steps")->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius h = h_factor * dx")->capture_default_str();
  cmd->add_option("--move", a->move, "Largest displacement per step, in dx (sets the time step)")->capture_default_str();
  cmd->add_option("--skin", a->skin, "Verlet skin as a fraction of the support radius")->capture_default_str();
  cmd->add_option("--method", a->method, "Method (any with a Laplacian and a gradient)")->capture_default_str();
  cmd->add_option("--method-opt", a->method_opts, "Method option key=value, or method:key=value (repeatable)");
  cmd->add_option("--warm-start", a->warm_start, "Start VRSPH's NNLS from each row's previous active set")
      ->check(boolean_validator())
      ->capture_default_str();
  cmd->add_option("--share-volumes", a->share_volumes,
                  "With --warm-start, VRSPH's gradient rows take the Laplacian's volumes where these meet the "
                  "Laplace conditions instead of solving their own NNLS (borrowed_volume_rate)")
      ->check(boolean_validator())
      ->capture_default_str();
  cmd->add_option("--periodic", a->periodic,
                  "Periodic axes x,y,z or all (given alone: all). Fully periodic: the Taylor-Green field moves the "
                  "particles; otherwise a cellular flow, periodic along these axes and tangential to the walls")
      ->expected(0, 1)
      ->default_str("all");
  cmd->add_flag("--div-a-grad", a->div_a_grad, "Keep div(a grad) too, a = 1 + f/2 (f the Laplacian's test field) given "
                                              "with the positions every step (div_a_grad_error)");
  cmd->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->callback([a] { run_update_bench(*a); });
}

}  // namespace vrsph::cli
