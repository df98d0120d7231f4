#include <optional>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/volumes.hpp>

namespace vrsph {

void neighbour_geometry(const Discretisation& disc, Index i, const Kernel& ker, Vec3* xji, Real* half_y) {
  const auto nbr = disc.neighbours.of(i);
  const auto dist = disc.neighbours.distances_of(i);
  const int cnt = static_cast<int>(nbr.size());
  ker.dW_over_r(dist.data(), half_y, cnt);
  const Vec3& xi = disc.cloud.positions[static_cast<std::size_t>(i)];
  for (int k = 0; k < cnt; ++k) {
    xji[k] = disc.cloud.positions[static_cast<std::size_t>(nbr[static_cast<std::size_t>(k)])] - xi;
    half_y[k] = -half_y[k];
  }
}

ReconstructedVolumes reconstruct_volumes(const Discretisation& disc, MomentConditions conditions,
                                         std::span<const char> rows, const NnlsOptions& nnls, MomentRows layout,
                                         std::span<const MomentTarget> targets) {
  const PointCloud& cloud = disc.cloud;
  const NeighbourList& nl = disc.neighbours;
  const Index n = cloud.size();
  check<InputError>(rows.empty() || static_cast<Index>(rows.size()) == n, "volume reconstruction: row mask has ",
                    rows.size(), " entries for ", n, " particles");
  check<InputError>(nl.distances.size() == nl.indices.size(), "VRSPH needs neighbour lists with cached distances");
  check<InputError>(targets.empty() || (conditions == MomentConditions::Laplace && static_cast<Index>(targets.size()) == n),
                    "volume reconstruction: ", targets.size(), " moment targets for ", n, " particles (Laplace only)");
  const int dim = cloud.dim;
  const int m = moment_rows(conditions, dim, layout);
  ReconstructedVolumes out;
  out.conditions = conditions;
  out.v.resize(static_cast<std::size_t>(nl.total()));
  out.residual.assign(static_cast<std::size_t>(n), 0.0);
  out.failed.assign(static_cast<std::size_t>(n), 0);
  out.iterations.assign(static_cast<std::size_t>(n), 0);
  out.positive.assign(static_cast<std::size_t>(n), 0);
  Index max_count = 0;
  for (Index i = 0; i < n; ++i) max_count = std::max(max_count, nl.count(i));
#pragma omp parallel
  {
    // Per-thread workspaces, sized once: no allocation inside the particle loop.
    NnlsSolver solver(m, static_cast<int>(max_count));
    std::vector<Real> A(static_cast<std::size_t>(m) * static_cast<std::size_t>(max_count)), b(static_cast<std::size_t>(m)),
        half_y(static_cast<std::size_t>(max_count));
    std::vector<Vec3> xji(static_cast<std::size_t>(max_count));
    std::optional<Kernel> ker;
#pragma omp for schedule(dynamic, 64)
    for (Index i = 0; i < n; ++i) {
      const auto si = static_cast<std::size_t>(i);
      Real* v = out.v.data() + nl.offsets[si];
      const int cnt = static_cast<int>(nl.count(i));
      const bool wanted = rows.empty() ? cloud.tags[si] != Tag::Ghost : rows[si] != 0;
      if (!wanted) {
        std::fill(v, v + cnt, 0.0);
        continue;
      }
      // The kernel changes only with the support radius (the same for every particle unless
      // h varies): rebuilding it per particle (a pow and checks) was ~2% of the volumes.
      if (!ker || nl.radius(i) != ker->support()) ker = disc.kernel_at(i);
      neighbour_geometry(disc, i, *ker, xji.data(), half_y.data());
      // Row-major: the layout the solver works on, so it copies nothing.
      build_moment_system(conditions, dim, xji.data(), half_y.data(), cnt, A.data(), b.data(), layout, MatrixOrder::RowMajor);
      if (!targets.empty()) moment_targets(dim, layout, targets[si], b.data());
      const NnlsResult r = solver.solve(A.data(), m, cnt, b.data(), v, nnls, MatrixOrder::RowMajor);
      out.residual[si] = r.residual;
      out.failed[si] = r.status != NnlsStatus::Converged;
      out.iterations[si] = r.iterations;
      out.positive[si] = r.passive;
    }
  }
  return out;
}

}  // namespace vrsph
