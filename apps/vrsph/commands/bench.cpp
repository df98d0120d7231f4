// `vrsph bench`: throughput measurements reported as ratios against a baseline
// measured in the same run (the machine is shared and noisy; absolute seconds are
// for orientation only).
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>
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

void set_threads(int threads) {
  check<ConfigError>(threads >= 0, "--threads must be >= 0 (0 = all cores)");
#ifdef _OPENMP
  omp_set_num_threads(threads == 0 ? omp_get_num_procs() : threads);
#else
  check<ConfigError>(threads <= 1, "this build has no OpenMP: --threads must be 1");
#endif
}

double peak_memory_mib() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
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
  nb->add_option("--seed", a->seed, "Random seed of the perturbation")->capture_default_str();
  nb->add_option("--format", a->out.format, "Output format: md, csv or json")->capture_default_str();
  nb->add_option("--output", a->out.output, "Write the table to this file instead of stdout");
  nb->callback([a] {
    check<ConfigError>(a->repeat >= 1, "--repeat must be >= 1");
    check<ConfigError>(a->dim >= 1 && a->dim <= 3, "--dim must be 1, 2 or 3");
    set_threads(a->threads);
    CloudSpec spec;
    spec.family = CloudFamily::Perturbed;
    spec.box = Domain::unit_box(a->dim);
    spec.n = a->n;
    spec.seed = a->seed;
    const StudyCloud sc = make_study_cloud(spec);
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
    emit(t, a->out, "{\"benchmark\":\"neighbours\",\"peak_memory_mib\":" + std::to_string(peak_memory_mib()) + "}", "", "",
         "", "");
  });
}

}  // namespace vrsph::cli
