// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/neighbours/brute_force.hpp>
#include "two_pass.hpp"

namespace vrsph {
namespace detail {

NeighbourList cell_list_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                               NeighbourList storage);
NeighbourList kd_tree_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params,
                             NeighbourList storage);
NeighbourList periodic_search(const PointCloud& cloud, const SearchParams& params, NeighbourList storage);  // periodic.cpp

namespace {
// A radius that covers much of the cloud makes the search itself O(N^2) in time
// before its exact count can refuse it. On large clouds, count the neighbours of a
// few evenly spread particles by brute force (cost 64 N) and refuse early when the
// extrapolated list would not fit.
void estimate_pairs_before_search(const PointCloud& cloud, const std::vector<Real>& radii, const SearchParams& params) {
  const Index n = cloud.size();
  constexpr Index exact_below = 20000, samples = 64;
  if (n < exact_below) return;  // the exact count pass is cheap enough
  double found = 0;
#pragma omp parallel for schedule(static) reduction(+ : found)
  for (Index s = 0; s < samples; ++s) {
    const auto i = static_cast<std::size_t>(static_cast<long long>(s) * n / samples);
    const Real r2 = radii[i] * radii[i];
    const Vec3& xi = cloud.positions[i];
    for (const Vec3& xj : cloud.positions) found += (xj - xi).squaredNorm() < r2 ? 1 : 0;
  }
  const double pairs = found / samples * static_cast<double>(n);
  check<ResourceError>(pairs <= static_cast<double>(std::numeric_limits<Index>::max()), "the neighbour list would have about ",
                       static_cast<long long>(pairs), " pairs (", found / samples, " neighbours per particle, estimated from ", samples,
                       " particles), more than the ", std::numeric_limits<Index>::max(),
                       " an index can count: reduce the smoothing radius (--h-factor) or the number of particles");
  check_memory_estimate(pairs * neighbour_pair_bytes(params),
                        concat("the neighbour list (about ", static_cast<long long>(pairs), " pairs, estimated from ", samples, " particles)"),
                        "reduce the smoothing radius (--h-factor) or the number of particles");
}
}  // namespace

std::vector<Real> resolve_radii(const PointCloud& cloud, const SearchParams& params) {
  validate(cloud);
  std::vector<Real> radii;
  if (params.radii.empty()) {
    check<InputError>(std::isfinite(params.radius) && params.radius > 0,
                      "search radius must be positive and finite, got ", params.radius);
    radii.assign(cloud.positions.size(), params.radius);
  } else {
    check<InputError>(params.radii.size() == cloud.positions.size(), "per-particle radii: got ", params.radii.size(),
                      " values for ", cloud.size(), " particles (size mismatch)");
    for (std::size_t i = 0; i < params.radii.size(); ++i)
      check<InputError>(std::isfinite(params.radii[i]) && params.radii[i] > 0, "search radius of particle ", i,
                        " must be positive and finite, got ", params.radii[i]);
    radii = params.radii;
  }
  check<InputError>(params.duplicate_tolerance >= 0, "duplicate tolerance must be >= 0");
  estimate_pairs_before_search(cloud, radii, params);
  return radii;
}

}  // namespace detail

NeighbourList find_neighbours(const PointCloud& cloud, const SearchParams& params) {
  return find_neighbours(cloud, params, NeighbourList{});
}

NeighbourList find_neighbours(const PointCloud& cloud, const SearchParams& params, NeighbourList storage) {
  if (params.wrap_periodic && cloud.domain.any_periodic()) return detail::periodic_search(cloud, params, std::move(storage));
  auto radii = detail::resolve_radii(cloud, params);
  if (params.backend == SearchBackend::KdTree)
    return detail::kd_tree_search(cloud, std::move(radii), params, std::move(storage));
  return detail::cell_list_search(cloud, std::move(radii), params, std::move(storage));
}

NeighbourList find_neighbours_brute_force(const PointCloud& cloud, const SearchParams& params) {
  auto radii = detail::resolve_radii(cloud, params);
  const Index n = cloud.size();
  auto visit = [&](Index i, Real, auto&& emit) {
    const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
    for (Index j = 0; j < n; ++j) emit(j, (cloud.positions[static_cast<std::size_t>(j)] - xi).squaredNorm());
  };
  return detail::two_pass_search(cloud, std::move(radii), params, visit);
}

}  // namespace vrsph
