#include <cmath>
#include <vrsph/neighbours/brute_force.hpp>
#include "two_pass.hpp"

namespace vrsph {
namespace detail {

NeighbourList cell_list_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params);
NeighbourList kd_tree_search(const PointCloud& cloud, std::vector<Real> radii, const SearchParams& params);

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
  return radii;
}

}  // namespace detail

NeighbourList find_neighbours(const PointCloud& cloud, const SearchParams& params) {
  auto radii = detail::resolve_radii(cloud, params);
  if (params.backend == SearchBackend::KdTree) return detail::kd_tree_search(cloud, std::move(radii), params);
  return detail::cell_list_search(cloud, std::move(radii), params);
}

NeighbourList find_neighbours_brute_force(const PointCloud& cloud, const SearchParams& params) {
  auto radii = detail::resolve_radii(cloud, params);
  const Index n = cloud.size();
  auto visit = [&](Index i, auto&& emit) {
    const Vec3& xi = cloud.positions[static_cast<std::size_t>(i)];
    for (Index j = 0; j < n; ++j) emit(j, (cloud.positions[static_cast<std::size_t>(j)] - xi).squaredNorm());
  };
  return detail::two_pass_search(cloud, std::move(radii), params, visit);
}

}  // namespace vrsph
