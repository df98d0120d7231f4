// SPDX-License-Identifier: BSD-3-Clause
// Google Benchmark: the two stages of VRSPH's volume reconstruction on perturbed lattices,
// one particle's system at a time — building the moment system, and the NNLS solve on
// systems built beforehand. Compare rows of one run with each
// other (the machine is shared); `vrsph bench volumes` reports the end-to-end throughput.
#include <benchmark/benchmark.h>
#include <map>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/methods/vrsph/moments.hpp>
#include <vrsph/methods/vrsph/nnls.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>
#include <vrsph/neighbours/search.hpp>

using namespace vrsph;

namespace {
// Moment systems of the first 4096 interior particles of a perturbed lattice.
struct Systems {
  int m = 0;
  std::vector<std::vector<Real>> A, b;
  std::vector<std::vector<Vec3>> xji;
  std::vector<std::vector<Real>> half_y;
};

const Systems& systems_for(int dim, int n) {
  static std::map<std::pair<int, int>, Systems> cache;
  Systems& s = cache[{dim, n}];
  if (s.m) return s;
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(dim);
  spec.n = n;
  const StudyCloud sc = make_study_cloud(spec);
  SearchParams sp;
  sp.radius = 3 * sc.dx;
  const NeighbourList nl = find_neighbours(sc.cloud, sp);
  const Discretisation disc{sc.cloud, nl, KernelType::CubicSpline, sc.dx};
  s.m = moment_rows(MomentConditions::Laplace, dim, MomentRows::Merged);
  for (Index i = 0; i < sc.cloud.size() && s.A.size() < 4096; ++i) {
    if (sc.cloud.tags[static_cast<std::size_t>(i)] != Tag::Interior) continue;
    const auto nbr = nl.of(i);
    std::vector<Vec3> x(nbr.size());
    std::vector<Real> hy(nbr.size());
    neighbour_geometry(disc, i, disc.kernel_at(i), x.data(), hy.data());
    std::vector<Real> A(static_cast<std::size_t>(s.m) * nbr.size()), b(static_cast<std::size_t>(s.m));
    build_moment_system(MomentConditions::Laplace, dim, x.data(), hy.data(), static_cast<int>(nbr.size()), A.data(), b.data(),
                        MomentRows::Merged);
    s.A.push_back(std::move(A));
    s.b.push_back(std::move(b));
    s.xji.push_back(std::move(x));
    s.half_y.push_back(std::move(hy));
  }
  return s;
}

void BM_BuildMomentSystem(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const Systems& s = systems_for(dim, dim == 2 ? 200 : 24);
  std::vector<Real> A(s.A.front().size() * 4), b(static_cast<std::size_t>(s.m));
  std::size_t p = 0;
  for (auto _ : state) {
    const auto& x = s.xji[p];
    A.resize(static_cast<std::size_t>(s.m) * x.size());
    build_moment_system(MomentConditions::Laplace, dim, x.data(), s.half_y[p].data(), static_cast<int>(x.size()), A.data(),
                        b.data(), MomentRows::Merged);
    benchmark::DoNotOptimize(A.data());
    p = (p + 1) % s.A.size();
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Nnls(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const Systems& s = systems_for(dim, dim == 2 ? 200 : 24);
  NnlsSolver solver;
  std::vector<Real> x(512);
  std::size_t p = 0;
  long iterations = 0;
  for (auto _ : state) {
    const int n = static_cast<int>(s.xji[p].size());
    iterations += solver.solve(s.A[p].data(), s.m, n, s.b[p].data(), x.data()).iterations;
    benchmark::DoNotOptimize(x.data());
    p = (p + 1) % s.A.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["nnls_iterations"] = static_cast<double>(iterations) / static_cast<double>(state.iterations());
}
}  // namespace

BENCHMARK(BM_BuildMomentSystem)->Arg(2)->Arg(3);
BENCHMARK(BM_Nnls)->Arg(2)->Arg(3);
// Fixed counts: for instruction counts under callgrind (the same systems in every run).
BENCHMARK(BM_Nnls)->Arg(2)->Iterations(3000);
BENCHMARK(BM_Nnls)->Arg(3)->Iterations(500);
