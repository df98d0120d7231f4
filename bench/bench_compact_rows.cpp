// SPDX-License-Identifier: BSD-3-Clause
// Google Benchmark: VRSPH's compact rows (rhs=compact, the default rows of a boundary value
// problem) on the interior of a perturbed lattice (on OpenMP's threads: OMP_NUM_THREADS=1 for one), with Example 5's coefficient
// a = 1 + |x|^2 and its gradient: each row's positive row of least truncation (a small linear
// program, DenseSimplex) against the NNLS's row (`compact_select=nnls`). Compare rows of one run
// with each other (the machine is shared); `vrsph bench solve` reports the stencil stage.
#include <benchmark/benchmark.h>
#include <map>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/methods/vrsph/compact_rows.hpp>
#include <vrsph/neighbours/search.hpp>

using namespace vrsph;

namespace {
struct Problem {
  StudyCloud sc;
  NeighbourList nl;
  Field a;
  Eigen::MatrixXd grad_a;
  std::vector<char> rows;
};

const Problem& problem_for(int dim) {
  static std::map<int, Problem> cache;
  Problem& p = cache[dim];
  if (!p.rows.empty()) return p;
  CloudSpec spec;
  spec.family = CloudFamily::Perturbed;
  spec.box = Domain::unit_box(dim);
  spec.n = dim == 2 ? 100 : 12;
  p.sc = make_study_cloud(spec);
  SearchParams sp;
  sp.radius = 3 * p.sc.dx;
  p.nl = find_neighbours(p.sc.cloud, sp);
  const Index n = p.sc.cloud.size();
  p.a.resize(n);
  p.grad_a.resize(n, dim);
  p.rows.assign(static_cast<std::size_t>(n), 0);
  for (Index i = 0; i < n; ++i) {
    const Vec3& x = p.sc.cloud.positions[static_cast<std::size_t>(i)];
    p.a[i] = 1 + x.squaredNorm();
    for (int k = 0; k < dim; ++k) p.grad_a(i, k) = 2 * x[k];
    p.rows[static_cast<std::size_t>(i)] = p.sc.cloud.tags[static_cast<std::size_t>(i)] == Tag::Interior;
  }
  return p;
}

// range(0): dimension; range(1): 1 = least truncation (the default), 0 = the NNLS's rows.
void BM_CompactRows(benchmark::State& state) {
  const int dim = static_cast<int>(state.range(0));
  const Problem& p = problem_for(dim);
  const Discretisation disc{p.sc.cloud, p.nl, KernelType::CubicSpline, p.sc.dx};
  CompactRowOptions o;  // vrsph's defaults (method options compact_*)
  o.tolerance = 1e-8;
  o.inner_support = 0.8;
  o.signed_average = true;
  o.wide_support = 1.25;
  o.least_truncation = state.range(1) != 0;
  Stencil s = make_stencil_pattern(p.nl, OperatorKind::Laplacian, dim, "vrsph");
  s.rhs.assign(s.col.size(), 0.0);
  Index admitted = 0;
  for (auto _ : state) {
    const CompactRows c = compact_rows(disc, p.rows, &p.a, &p.grad_a, o, s);
    admitted = static_cast<Index>(std::count(c.ok.begin(), c.ok.end(), 1));
    benchmark::DoNotOptimize(s.values[0].data());
  }
  const auto interior = static_cast<Index>(std::count(p.rows.begin(), p.rows.end(), 1));
  state.SetItemsProcessed(state.iterations() * interior);
  state.counters["rows"] = static_cast<double>(interior);
  state.counters["admitted"] = static_cast<double>(admitted);
}
}  // namespace

BENCHMARK(BM_CompactRows)->ArgsProduct({{2, 3}, {1, 0}})->Unit(benchmark::kMillisecond);
