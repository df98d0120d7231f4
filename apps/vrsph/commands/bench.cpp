// SPDX-License-Identifier: BSD-3-Clause
// `vrsph bench`: throughput measurements reported as ratios against a baseline
// measured in the same run (the machine is shared and noisy; absolute seconds are
// for orientation only).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <vrsph/io/json.hpp>
#include <fstream>
#include <sstream>
#include <iostream>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/sph/sph.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include "../cli_common.hpp"
#include "../commands.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vrsph::cli {

namespace {
struct BenchArgs {
  int dim = 2, n = 1000, repeat = 3, threads = 1;
  double h_factor = 3;
  std::uint64_t seed = 1;
  OutputOptions out;
};

// The benchmark cloud: a perturbed layout-A unit lattice, (n+1)^d particles.
StudyCloud bench_cloud(const BenchArgs& a) {
  check<ConfigError>(a.repeat >= 1, "--repeat must be >= 1");
  check<ConfigError>(a.dim >= 1 && a.dim <= 3, "--dim must be 1, 2 or 3");
  // Repetitions times particles: each repetition rebuilds every particle's row (~1e-6 s each
  // for VRSPH on one core); beyond 1e10 row builds a benchmark runs for hours.
  const double particles = std::pow(a.n + 1.0, a.dim), rows = particles * a.repeat;
  check<ConfigError>(a.repeat <= 10000 && rows <= 1e10, "--repeat ", a.repeat, " x ", particles, " particles = ", rows, " row builds per method (hours); lower --repeat or --n (at most 10000 "
                     "repetitions and 1e10 row builds)");
  set_thread_count(a.threads);
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(a.dim);
  spec.n = a.n;
  spec.seed = a.seed;
  return make_study_cloud(spec);
}

template <class F>
double best_of(int repeat, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}
}  // namespace

// VRSPH Laplace volume reconstruction alone (neighbour search excluded), against the
// traditional SPH stencil build and the textbook NNLS in the same run.
void add_solve_bench(CLI::App& bench);   // bench_solve.cpp
void add_accuracy_bench(CLI::App& bench);  // bench_accuracy.cpp
void add_update_bench(CLI::App& bench);  // bench_update.cpp

void add_volumes_bench(CLI::App& bench) {
  auto a = std::make_shared<BenchArgs>();
  auto reference_sample = std::make_shared<int>(20000);
  auto* cmd = bench.add_subcommand("volumes", "VRSPH volume reconstruction throughput vs SPH stencil and textbook NNLS");
  cmd->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction of the perturbed unit lattice ((n+1)^d particles)")->capture_default_str();
  cmd->add_option("--h-factor", a->h_factor, "Support radius h = h_factor * dx")->capture_default_str();
  cmd->add_option("--repeat", a->repeat, "Repetitions; the best time is reported")->capture_default_str();
  cmd->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  cmd->add_option("--reference-sample", *reference_sample, "Particles timed with the textbook NNLS (it is slow)")->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->callback([a, reference_sample] {
    check<ConfigError>(*reference_sample >= 0, "--reference-sample must be >= 0");
    const StudyCloud sc = bench_cloud(*a);
    SearchParams sp;
    sp.radius = a->h_factor * sc.dx;
    const NeighbourList nl = find_neighbours(sc.cloud, sp);
    const Discretisation disc{sc.cloud, nl, KernelType::CubicSpline, sc.cloud.spacing};
    const auto N = static_cast<double>(sc.cloud.size() - sc.cloud.count(Tag::Ghost));
    ReconstructedVolumes vol;
    const double t_vol = best_of(a->repeat, [&] { vol = reconstruct_volumes(disc, MomentConditions::Laplace); });
    const auto sph = builtin_methods().create("sph");
    const double t_sph = best_of(a->repeat, [&] { (void)sph->build(disc, {OperatorKind::Laplacian}); });
    // Textbook NNLS on a sample of interior particles (single solve each, same systems).
    const int m = moment_rows(MomentConditions::Laplace, a->dim);
    std::vector<Index> sample;
    for (Index i = 0; i < sc.cloud.size() && static_cast<int>(sample.size()) < *reference_sample; ++i)
      if (sc.cloud.tags[static_cast<std::size_t>(i)] == Tag::Interior) sample.push_back(i);
    double t_ref = 0, t_fast_sample = 0, max_diff = 0;
    if (!sample.empty()) {
      std::vector<Eigen::MatrixXd> As;
      std::vector<Eigen::VectorXd> bs;
      for (Index i : sample) {
        const auto nbr = nl.of(i);
        std::vector<Vec3> xji(nbr.size());
        std::vector<Real> hy(nbr.size());
        neighbour_geometry(disc, i, disc.kernel_at(i), xji.data(), hy.data());
        As.emplace_back(m, static_cast<Eigen::Index>(nbr.size()));
        bs.emplace_back(m);
        build_moment_system(MomentConditions::Laplace, a->dim, xji.data(), hy.data(), static_cast<int>(nbr.size()),
                            As.back().data(), bs.back().data());
      }
      std::vector<double> res_ref(sample.size()), res_fast(sample.size());
      t_ref = best_of(1, [&] {
        Eigen::VectorXd x;
        for (std::size_t s = 0; s < As.size(); ++s) res_ref[s] = nnls_reference(As[s], bs[s], x).residual;
      });
      t_fast_sample = best_of(a->repeat, [&] {
        NnlsSolver solver;
        std::vector<Real> x(256);
        for (std::size_t s = 0; s < As.size(); ++s) {
          x.resize(static_cast<std::size_t>(As[s].cols()));
          res_fast[s] = solver.solve(As[s].data(), m, static_cast<int>(As[s].cols()), bs[s].data(), x.data()).residual;
        }
      });
      for (std::size_t s = 0; s < As.size(); ++s) max_diff = std::max(max_diff, std::abs(res_ref[s] - res_fast[s]));
    }
    Table t;
    t.columns = {"stage", "particles", "threads", "seconds", "particles_per_second", "ratio_to_vrsph_volumes"};
    auto row = [&](const std::string& name, double particles, double seconds) {
      t.add_row({{"stage", name}, {"particles", static_cast<long long>(particles)}, {"threads", static_cast<long long>(a->threads)},
                 {"seconds", seconds}, {"particles_per_second", particles / seconds}, {"ratio_to_vrsph_volumes", (seconds / particles) / (t_vol / N)}});
    };
    row("vrsph volumes (fast NNLS)", N, t_vol);
    row("sph laplacian stencil", N, t_sph);
    if (!sample.empty()) {
      row("fast NNLS only (sample)", static_cast<double>(sample.size()), t_fast_sample);
      row("textbook NNLS only (sample)", static_cast<double>(sample.size()), t_ref);
    }
    const Json extra = Json::object(
        {{"benchmark", "volumes"},
         {"particles", static_cast<long long>(N)},
         {"seconds", t_vol},
         {"particles_per_second", N / t_vol},
         {"neighbours_mean", static_cast<double>(nl.total()) / static_cast<double>(sc.cloud.size())},
         {"textbook_speedup", t_fast_sample > 0 ? t_ref / t_fast_sample : 0.0},
         {"max_residual_difference", max_diff},
         {"peak_memory_mib", peak_memory_mib()}});
    emit(t, a->out, extra, "", "", "", "");
  });
}

// [QW] Table 1: time to build the Laplacian stencil of each method, repeated, as ratios to
// SPH in the same run; separately the summation-density volumes m/rho the others need.
void add_stencils_bench(CLI::App& bench) {
  auto a = std::make_shared<BenchArgs>();
  a->n = 128;
  a->repeat = 10;
  auto methods = std::make_shared<std::string>("sph,vrsph,fpm,cspm,kgf");
  auto factors = std::make_shared<std::string>("3");
  auto* cmd = bench.add_subcommand("stencils", "[QW] Table 1: Laplacian stencil build time per method, ratio to SPH");
  cmd->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->capture_default_str();
  cmd->add_option("--n", a->n, "Intervals per direction of the perturbed unit lattice ([QW]: 2^7)")->capture_default_str();
  cmd->add_option("--h-factor", *factors, "Comma-separated h/dx values ([QW]: 3,4,5)")->capture_default_str();
  cmd->add_option("--repeat", a->repeat, "Builds per method; seconds = their total ([QW]: 10)")->capture_default_str();
  cmd->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--method", *methods, "Comma-separated methods (sph is always timed as the baseline)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  cmd->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  cmd->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  cmd->callback([a, methods, factors] {
    auto names = parse_name_list(*methods, "--method");
    if (std::find(names.begin(), names.end(), "sph") == names.end()) names.insert(names.begin(), "sph");
    const std::vector<double> kappas = parse_real_list(*factors, "--h-factor");
    for (double k : kappas) {
      check<ConfigError>(std::isfinite(k) && k > 0, "--h-factor: '", k, "' is not a positive number");
      // As every other command: a support wider than the domain is no local stencil (and its
      // neighbour list would be the whole cloud per particle).
      check_support_is_local(k / a->n, std::sqrt(static_cast<Real>(a->dim)), k);
    }
    // [QW] Table 1 seconds (h/dx = 3, 4, 5), for the comparison column.
    const std::map<std::string, std::array<double, 3>> paper{{"vrsph", {28.2344, 42.4219, 55.9844}},
                                                             {"sph", {9.5312, 17.6094, 26.75}},
                                                             {"fpm", {25.5625, 44.2188, 65.9219}},
                                                             {"cspm", {19.9688, 35.3438, 47.0625}},
                                                             {"kgf", {26.75, 44.5156, 65.5312}},
                                                             {"volumes m/rho", {4.4219, 7.1719, 10.6094}}};
    const StudyCloud sc = bench_cloud(*a);
    Table t;
    t.columns = {"method", "h_factor", "particles", "repeat", "threads", "seconds", "seconds_per_build", "ratio_to_sph",
                 "paper_seconds", "paper_ratio_to_sph"};
    Json per_method = Json::object();
    for (double kappa : kappas) {
      SearchParams sp;
      sp.radius = kappa * sc.dx;
      const NeighbourList nl = find_neighbours(sc.cloud, sp);
      const Discretisation disc{sc.cloud, nl, KernelType::CubicSpline, sc.cloud.spacing};
      std::map<std::string, double> seconds;
      for (const auto& m : names) {
        const auto method = builtin_methods().create(m);
        const auto t0 = std::chrono::steady_clock::now();
        for (int r = 0; r < a->repeat; ++r) (void)method->build(disc, {OperatorKind::Laplacian});
        seconds[m] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      {
        const auto t0 = std::chrono::steady_clock::now();
        for (int r = 0; r < a->repeat; ++r) (void)sph_volumes(disc, SphVolume::Shepard);
        seconds["volumes m/rho"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      const int col = kappa == 3 ? 0 : kappa == 4 ? 1 : kappa == 5 ? 2 : -1;
      auto order = names;
      order.push_back("volumes m/rho");
      for (const auto& m : order) {
        const auto it = paper.find(m);
        const double ps = col >= 0 && it != paper.end() ? it->second[static_cast<std::size_t>(col)] : std::nan("");
        const double pr = col >= 0 && it != paper.end() ? ps / paper.at("sph")[static_cast<std::size_t>(col)] : std::nan("");
        t.add_row({{"method", m}, {"h_factor", kappa}, {"particles", static_cast<long long>(sc.cloud.size())},
                   {"repeat", static_cast<long long>(a->repeat)}, {"threads", static_cast<long long>(a->threads)},
                   {"seconds", seconds[m]}, {"seconds_per_build", seconds[m] / a->repeat},
                   {"ratio_to_sph", seconds[m] / seconds["sph"]}, {"paper_seconds", ps}, {"paper_ratio_to_sph", pr}});
        if (kappa == kappas.front()) per_method[m] = Json::object({{"seconds", seconds[m]}, {"ratio_to_sph", seconds[m] / seconds["sph"]}});
      }
    }
    Json extra;
    extra["benchmark"] = "stencils";
    extra["methods"] = per_method;
    extra["peak_memory_mib"] = peak_memory_mib();
    emit(t, a->out, extra, "", "", "", "");
  });
}

void add_bench_command(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Throughput benchmarks (ratios against an in-run baseline)");
  bench->require_subcommand(1);
  auto a = std::make_shared<BenchArgs>();
  auto* nb = bench->add_subcommand("neighbours", "Neighbour search: cell list (baseline) vs nanoflann k-d tree");
  nb->add_option("--dim", a->dim, "Dimension 1, 2 or 3")->capture_default_str();
  nb->add_option("--n", a->n, "Intervals per direction of the perturbed unit lattice ((n+1)^d particles)")->capture_default_str();
  nb->add_option("--h-factor", a->h_factor, "Search radius h = h_factor * dx")->capture_default_str();
  nb->add_option("--repeat", a->repeat, "Repetitions; the best time is reported")->capture_default_str();
  nb->add_option("--threads", a->threads, "OpenMP threads (0 = all cores)")->capture_default_str();
  nb->add_option("--seed", a->seed, "Random seed of the perturbation")->check(seed_validator())->capture_default_str();
  nb->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  nb->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  nb->callback([a] {
    const StudyCloud sc = bench_cloud(*a);
    SearchParams sp;
    sp.radius = a->h_factor * sc.dx;
    Table t;
    t.columns = {"backend", "particles", "pairs", "threads", "seconds", "particles_per_second", "ratio_to_cell_list"};
    double base = 0;
    for (auto backend : {SearchBackend::CellList, SearchBackend::KdTree}) {
      sp.backend = backend;
      Index pairs = 0;
      const double s = best_of(a->repeat, [&] { pairs = find_neighbours(sc.cloud, sp).total(); });
      if (backend == SearchBackend::CellList) base = s;
      t.add_row({{"backend", std::string(backend == SearchBackend::CellList ? "cell-list" : "kd-tree (nanoflann)")},
                 {"particles", static_cast<long long>(sc.cloud.size())},
                 {"pairs", static_cast<long long>(pairs)},
                 {"threads", static_cast<long long>(a->threads)},
                 {"seconds", s},
                 {"particles_per_second", static_cast<double>(sc.cloud.size()) / s},
                 {"ratio_to_cell_list", s / base}});
    }
    emit(t, a->out, Json::object({{"benchmark", "neighbours"}, {"peak_memory_mib", peak_memory_mib()}}), "", "", "", "");
  });
  add_volumes_bench(*bench);
  add_stencils_bench(*bench);
  add_solve_bench(*bench);
  add_accuracy_bench(*bench);
  add_update_bench(*bench);
}

}  // namespace vrsph::cli
