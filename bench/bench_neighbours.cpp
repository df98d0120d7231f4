// SPDX-License-Identifier: BSD-3-Clause
// Google Benchmark: neighbour search backends and the SPH stencil build on perturbed
// unit lattices. Compare rows of one run with each other (the machine is shared);
// `vrsph bench neighbours` reports the same comparison as ratios.
#include <benchmark/benchmark.h>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>

using namespace vrsph;

namespace {
const StudyCloud& cloud_for(int dim, int n) {
  static std::map<std::pair<int, int>, StudyCloud> cache;
  auto& c = cache[{dim, n}];
  if (c.cloud.size() == 0) {
    CloudSpec spec;
    spec.family = CloudFamily::Perturbed;
    spec.box = Domain::unit_box(dim);
    spec.n = n;
    c = make_study_cloud(spec);
  }
  return c;
}

void BM_Search(benchmark::State& state, SearchBackend backend) {
  const int dim = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const StudyCloud& sc = cloud_for(dim, n);
  SearchParams sp;
  sp.radius = 3 * sc.dx;
  sp.backend = backend;
  for (auto _ : state) benchmark::DoNotOptimize(find_neighbours(sc.cloud, sp).total());
  state.SetItemsProcessed(state.iterations() * sc.cloud.size());
}

void BM_SphLaplacian(benchmark::State& state) {
  const StudyCloud& sc = cloud_for(2, static_cast<int>(state.range(0)));
  SearchParams sp;
  sp.radius = 3 * sc.dx;
  const NeighbourList nl = find_neighbours(sc.cloud, sp);
  const auto sph = builtin_methods().create("sph");
  for (auto _ : state)
    benchmark::DoNotOptimize(sph->build({sc.cloud, nl, KernelType::CubicSpline, sc.cloud.spacing}, {OperatorKind::Laplacian}).nnz());
  state.SetItemsProcessed(state.iterations() * sc.cloud.size());
}
}  // namespace

BENCHMARK_CAPTURE(BM_Search, cell_list, SearchBackend::CellList)->Args({2, 300})->Args({3, 40})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Search, kd_tree, SearchBackend::KdTree)->Args({2, 300})->Args({3, 40})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphLaplacian)->Arg(300)->Unit(benchmark::kMillisecond);
