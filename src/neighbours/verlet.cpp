// SPDX-License-Identifier: BSD-3-Clause
// Verlet-skin neighbour lists (verlet.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/neighbours/verlet.hpp>
#include "two_pass.hpp"

namespace vrsph {

namespace {
// The image of j that i sees on a periodic box: per periodic axis the shift that brings
// x_j - x_i into [-L/2, L/2] (unique within the radius: the period exceeds twice it).
std::uint8_t minimum_image_code(const Domain& d, const Vec3& xi, const Vec3& xj) {
  int code = 0, place = 1;
  for (int k = 0; k < 3; ++k, place *= 3) {
    int s = 0;
    if (k < d.dim && d.periodic[static_cast<std::size_t>(k)]) {
      const Real dk = xj[k] - xi[k], half = 0.5 * d.period(k);
      s = dk > half ? -1 : dk < -half ? 1 : 0;
    }
    code += (s + 1) * place;
  }
  return static_cast<std::uint8_t>(code);
}

// x - y with the periodic axes taken to the nearest image: how far a particle moved.
Real displacement(const Domain& d, bool periodic, const Vec3& x, const Vec3& y) {
  Vec3 dx = x - y;
  if (periodic)
    for (int k = 0; k < d.dim; ++k)
      if (d.periodic[static_cast<std::size_t>(k)]) dx[k] -= d.period(k) * std::round(dx[k] / d.period(k));
  return dx.norm();
}
}  // namespace

VerletNeighbours::VerletNeighbours(SearchParams params, Real skin) : params_(std::move(params)), skin_(skin) {
  check<InputError>(std::isfinite(skin) && skin >= 0, "Verlet skin must be finite and >= 0, got ", skin);
  params_.cache_distances = true;
}

const NeighbourList& VerletNeighbours::update(const PointCloud& cloud) {
  validate(cloud);
  if (size_ < 0) {
    size_ = cloud.size();
    dim_ = cloud.dim;
    list_.radii = detail::resolve_radii(cloud, params_);
    const bool periodic = params_.wrap_periodic && cloud.domain.any_periodic();
    if (periodic) {  // radius + skin below half of every period
      const Real r = *std::max_element(list_.radii.begin(), list_.radii.end());
      period_limit_ = std::numeric_limits<Real>::infinity();
      for (int k = 0; k < cloud.dim; ++k)
        if (cloud.domain.periodic[static_cast<std::size_t>(k)]) period_limit_ = std::min(period_limit_, 0.499 * cloud.domain.period(k));
      skin_ = std::min(skin_, std::max(0.0, period_limit_ - r));
    }
  }
  check<InputError>(cloud.size() == size_ && cloud.dim == dim_, "neighbour update: the cloud has ", cloud.size(),
                    " particles in ", cloud.dim, "D, the list was built for ", size_, " in ", dim_,
                    "D (particles cannot be added or removed: build a new list)");
  if (params_.wrap_periodic && cloud.domain.any_periodic())
    check_periodic_cloud(cloud, *std::max_element(list_.radii.begin(), list_.radii.end()));
  last_searched_ = searched_at_.empty() || radii_grew_ || moved_too_far(cloud);
  if (last_searched_) search(cloud);
  refilter(cloud);
  (last_searched_ ? searches_ : refilters_) += 1;
  return list_;
}

void VerletNeighbours::search(const PointCloud& cloud) {
  SearchParams sp = params_;
  sp.radii.resize(list_.radii.size());
  for (std::size_t i = 0; i < sp.radii.size(); ++i) sp.radii[i] = list_.radii[i] + skin_;
  sp.cache_distances = false;
  sp.min_neighbours = 0;          // held to the real radius by refilter
  sp.duplicate_tolerance = 0;     // likewise
  // The last candidates' arrays are the new ones' storage; a search that throws leaves none,
  // and the cleared positions make the next update search again.
  searched_at_.clear();
  candidates_ = find_neighbours(cloud, sp, std::move(candidates_));
  searched_at_ = cloud.positions;
  searched_radii_ = list_.radii;
  radii_grew_ = false;
}

void VerletNeighbours::set_radii(std::vector<Real> radii) {
  check<InputError>(size_ >= 0, "neighbour radii: set after the first update (the list has no particles yet)");
  check<InputError>(static_cast<Index>(radii.size()) == size_, "neighbour radii: ", radii.size(), " radii for ", size_,
                    " particles");
  for (std::size_t i = 0; i < radii.size(); ++i) {
    check<InputError>(std::isfinite(radii[i]) && radii[i] > 0, "neighbour radii: the radius of particle ", i,
                      " must be positive and finite, got ", radii[i]);
    check<InputError>(period_limit_ == 0 || radii[i] + skin_ < period_limit_, "neighbour radii: the radius ", radii[i],
                      " of particle ", i, " plus the skin ", skin_, " reaches half the box's shortest period (",
                      period_limit_ / 0.499, "): a particle would meet two images of one neighbour");
  }
  // Whether the candidates (searched with searched_radii_ + skin) still hold every pair the new
  // radii ask for: only the radii now set count, not those set since the search and replaced.
  radii_grew_ = false;
  for (std::size_t i = 0; i < radii.size() && !searched_radii_.empty() && !radii_grew_; ++i)
    radii_grew_ = radii[i] > searched_radii_[i];
  list_.radii = std::move(radii);
}

bool VerletNeighbours::moved_too_far(const PointCloud& cloud) const {
  const bool periodic = params_.wrap_periodic && cloud.domain.any_periodic();
  // The two largest displacements, per thread and then over the threads.
  auto keep_two_largest = [](Real d, Real& first, Real& second) {
    if (d > first) {
      second = first;
      first = d;
    } else if (d > second) {
      second = d;
    }
  };
  Real d1 = 0, d2 = 0;
#pragma omp parallel
  {
    Real t1 = 0, t2 = 0;
#pragma omp for schedule(static) nowait
    for (Index i = 0; i < size_; ++i)
      keep_two_largest(displacement(cloud.domain, periodic, cloud.positions[static_cast<std::size_t>(i)],
                                    searched_at_[static_cast<std::size_t>(i)]),
                       t1, t2);
#pragma omp critical(vrsph_verlet_displacement)
    {
      keep_two_largest(t1, d1, d2);
      keep_two_largest(t2, d1, d2);
    }
  }
  return !(d1 + d2 <= skin_);
}

// The candidates within the radius at the current positions: each row's kept pairs packed at
// the start of its candidate slots, then the rows moved together (the CSR the methods read).
void VerletNeighbours::refilter(const PointCloud& cloud) {
  const Index n = size_;
  const Domain& dom = cloud.domain;
  const bool periodic = params_.wrap_periodic && dom.any_periodic();
  const auto total = static_cast<std::size_t>(candidates_.total());
  resize_for_overwrite(scratch_index_, total);  // overwritten below: no copy, no zeros
  resize_for_overwrite(scratch_distance_, total);
  if (periodic) scratch_shift_.resize(total);
  kept_.resize(static_cast<std::size_t>(n));
  const Real tol2 = params_.duplicate_tolerance * params_.duplicate_tolerance;
  long long duplicate = std::numeric_limits<long long>::max();  // lowest i * n + j
#pragma omp parallel for schedule(dynamic, 256) reduction(min : duplicate)
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Real r2max = list_.radii[si] * list_.radii[si], dup2 = tol2 * r2max;
    const Vec3& xi = cloud.positions[si];
    const auto row = candidates_.of(i);
    const auto begin = static_cast<std::size_t>(candidates_.offsets[si]);
    std::size_t at = begin;
    for (const Index j : row) {
      const Vec3& xj = cloud.positions[static_cast<std::size_t>(j)];
      const std::uint8_t code = periodic ? minimum_image_code(dom, xi, xj) : no_shift;
      const Real r2 = code == no_shift ? (xj - xi).squaredNorm() : (Vec3(xj + periodic_shift(dom, code)) - xi).squaredNorm();
      if (j != i && r2 <= dup2) duplicate = std::min(duplicate, static_cast<long long>(std::min(i, j)) * n + std::max(i, j));
      // Written whether kept or not, then passed over: as a branch around the stores, the
      // (unpredictable) test cost more than the stores (two_pass.hpp).
      scratch_index_[at] = j;
      scratch_distance_[at] = std::sqrt(r2);
      if (periodic) scratch_shift_[at] = code;
      at += (j == i ? params_.include_self : r2 < r2max) ? 1 : 0;
    }
    kept_[si] = static_cast<Index>(at - begin);
  }
  if (duplicate != std::numeric_limits<long long>::max()) {
    const auto a = static_cast<std::size_t>(duplicate / n), b = static_cast<std::size_t>(duplicate % n);
    detail::throw_duplicate(cloud, duplicate / n, duplicate % n, params_.duplicate_tolerance,
                            std::max(list_.radii[a], list_.radii[b]));
  }
  // The new row pointers are checked before they replace the list's: a refused update leaves
  // the last list as it was.
  next_.offsets.resize(static_cast<std::size_t>(n) + 1);
  next_.offsets[0] = 0;
  for (Index i = 0; i < n; ++i) next_.offsets[static_cast<std::size_t>(i) + 1] = next_.offsets[static_cast<std::size_t>(i)] + kept_[static_cast<std::size_t>(i)];
  detail::check_min_neighbours(cloud, next_, list_.radii, params_.min_neighbours, params_.include_self);
  list_.offsets.swap(next_.offsets);
  const auto pairs = static_cast<std::size_t>(list_.total());
  resize_for_overwrite(list_.indices, pairs);
  resize_for_overwrite(list_.distances, pairs);
  if (periodic) list_.shifts.resize(pairs);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const auto from = static_cast<std::ptrdiff_t>(candidates_.offsets[si]), to = static_cast<std::ptrdiff_t>(list_.offsets[si]);
    const auto cnt = static_cast<std::ptrdiff_t>(kept_[si]);
    std::copy(scratch_index_.begin() + from, scratch_index_.begin() + from + cnt, list_.indices.begin() + to);
    std::copy(scratch_distance_.begin() + from, scratch_distance_.begin() + from + cnt, list_.distances.begin() + to);
    if (periodic)
      std::copy(scratch_shift_.begin() + from, scratch_shift_.begin() + from + cnt, list_.shifts.begin() + to);
  }
}

}  // namespace vrsph
