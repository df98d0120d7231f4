// SPDX-License-Identifier: BSD-3-Clause
// Stage 2 of the solve pipeline (bvp_pipeline.hpp): the spacing, the support radius and the
// partition. The halo must hold what a row reads: reach() supports of the method (2 for
// D2 = D D and for Shepard/Voronoi volumes of the neighbours, 3 for their VRSPH volumes).
// In serial the partition is the whole cloud and every halo test below passes at once.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/search.hpp>
#include "bvp_pipeline.hpp"

namespace vrsph::detail {

namespace {
constexpr Real kHaloMargin = 1 + 1e-9;

// The halo to widen to when the current one does not hold `need`: need itself, at least twice
// the current. A periodic box's halo holds the images across its faces, which must stay within
// one period (periodic_images): an estimate made before the halo held those images can ask for
// more (a particle beside a face, seeing no one across it, gets a Voronoi cell open to the far
// side: a covering radius of the box's size), so beyond that bound the halo doubles instead, and
// the request is refused only once the halo has reached the bound.
Real next_halo_width(const Partition& part, Real need, const char* what) {
  const Real wider = std::max(need, 2 * part.halo_width());
  // +infinity without a periodic axis; over the ranks, so that every rank widens alike (a rank
  // whose part is empty may not know the box).
  const Real period = min_over_ranks(part.comm(), part.local().domain.shortest_period());
  const Real bound = 0.999 * period;
  if (wider < bound) return wider;
  check<ConfigError>(part.halo_width() < bound, what, " needs particles up to ", need,
                     " away, beyond one period ", period, " of the periodic box; use more particles or a longer box");
  return std::min(2 * part.halo_width(), bound);
}

// Covering: h = kappa max(dx, r_N), r_N exact from each rank's owned Voronoi cells when the
// halo holds every particle within 2 r_N of the owned ones (covering_radius.hpp); the halo
// must also hold reach x h. Widen and partition again until both hold.
void covering_support(Partition& part, const BvpSolveOptions& o, Real reach, Support& sup) {
  for (;;) {
    CoveringRadius mine;
    part.stage([&] { mine = covering_radius_of_owned(part.local(), part.owned(), sup.spacing); });
    const Real r = max_over_ranks(part.comm(), mine.radius), h = o.h_factor * std::max(sup.spacing, r);
    const Real need = std::max(2 * r, reach * h) * kHaloMargin;
    if (need <= part.halo_width()) {
      sup.covering_radius = r;
      sup.h = h;
      return;
    }
    part.widen(next_halo_width(part, need, "the covering radius"));
  }
}

// knn: h_i = kappa r_k(i), exact on the owner when every particle within r_k(i) is local;
// the halo must also hold reach x max h_i. h is reported as the mean radius.
void knn_support(Partition& part, const BvpSolveOptions& o, Real reach, Support& sup) {
  const int k = o.h_knn > 0 ? o.h_knn : 2 * std::max(part.local().dim, 1);
  for (;;) {
    std::vector<Real> rk;
    part.stage([&] { rk = kth_neighbour_distance(part.local(), k); });
    Real local_max = 0;
    for (Index i = 0; i < part.local_size(); ++i)
      if (part.owned()[static_cast<std::size_t>(i)]) local_max = std::max(local_max, rk[static_cast<std::size_t>(i)]);
    const Real r_max = max_over_ranks(part.comm(), local_max);
    const Real need = std::max(r_max, reach * o.h_factor * r_max) * kHaloMargin;
    if (r_max <= part.halo_width() && need <= part.halo_width()) {
      Field r(part.local_size());
      for (Index i = 0; i < r.size(); ++i) r[i] = o.h_factor * rk[static_cast<std::size_t>(i)];
      part.update_halo(r);  // the halo's radii are their owners' (exact) ones
      sup.radii.assign(r.data(), r.data() + r.size());
      double sum = 0;
      for (Index i = 0; i < r.size(); ++i)
        if (part.owned()[static_cast<std::size_t>(i)]) sum += r[i];
      sup.h = sum_over_ranks(part.comm(), sum) / static_cast<Real>(part.global_size());
      return;
    }
    part.widen(next_halo_width(part, need, "the k-th neighbour distance"));
  }
}

// The support must be local: no wider than the whole cloud (ghosts left out).
void check_local_support(const Partition& part, const BvpSolveOptions& o, const Support& sup) {
  const PointCloud& cloud = part.local();
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (Index i = 0; i < cloud.size(); ++i)
    if (cloud.tags[static_cast<std::size_t>(i)] != Tag::Ghost) {
      lo = lo.cwiseMin(cloud.positions[static_cast<std::size_t>(i)]);
      hi = hi.cwiseMax(cloud.positions[static_cast<std::size_t>(i)]);
    }
  for (int k = 0; k < 3; ++k) {
    lo[k] = min_over_ranks(part.comm(), lo[k]);
    hi[k] = max_over_ranks(part.comm(), hi[k]);
  }
  const Real extent = lo.allFinite() ? (hi - lo).norm() : std::numeric_limits<Real>::infinity();
  const Real h_max = sup.radii.empty() ? sup.h
                                       : max_over_ranks(part.comm(), *std::max_element(sup.radii.begin(), sup.radii.end()));
  part.stage([&] { check_support_is_local(h_max, extent, o.h > 0 ? 0 : o.h_factor); });
}
}  // namespace

std::unique_ptr<Partition> choose_support(const PointCloud& chunk, const BvpSolveOptions& o, Real reach, Support& sup) {
  const Communicator& comm = o.communicator;
  sup.spacing = o.spacing > 0 ? o.spacing : spacing_over_ranks(chunk, comm);
  collective(comm, [&] {
    check<InputError>(std::isfinite(sup.spacing) && sup.spacing > 0, "particle spacing must be positive, got ", sup.spacing);
  });
  sup.h = o.h > 0 ? o.h : o.h_factor * sup.spacing;
  const bool knn = o.h <= 0 && o.h_mode == SmoothingMode::Knn, covering = o.h <= 0 && o.h_mode == SmoothingMode::Covering;
  if (covering) {
    const long long n = sum_over_ranks(comm, static_cast<long long>(chunk.size()));
    const int dim = static_cast<int>(max_over_ranks(comm, static_cast<double>(chunk.size() ? chunk.dim : 0)));
    collective(comm, [&] {
      check<ConfigError>(chunk.size() == 0 || chunk.domain.shape != Domain::Shape::None,
                         "--h-mode covering needs a known domain (box or ball) for the covering radius; a cloud "
                         "without one (e.g. read from a file) cannot use it: use fixed or knn");
      check<InputError>(n > dim, "the covering radius needs more than ", dim, " particles");
    });
  }
  const bool periodic = any_rank(comm, chunk.domain.any_periodic());
  if (periodic) collective(comm, [&] { check_periodic_cloud(chunk, sup.h); });
  auto part = make_partition(chunk, reach * sup.h * kHaloMargin, comm);
  // On a periodic box the local cloud holds the images (its halo): the covering radius and each
  // k-th distance are the periodic ones once the halo reaches far enough, as across ranks.
  if (covering) covering_support(*part, o, reach, sup);
  if (knn) knn_support(*part, o, reach, sup);
  if (periodic && (knn || covering)) {
    const Real h_max = max_over_ranks(comm, sup.radii.empty() ? sup.h : *std::max_element(sup.radii.begin(), sup.radii.end()));
    collective(comm, [&] { check_periodic_cloud(chunk, h_max); });
  }
  check_local_support(*part, o, sup);
  return part;
}

}  // namespace vrsph::detail
