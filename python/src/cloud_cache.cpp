// SPDX-License-Identifier: BSD-3-Clause
#include "cloud_cache.hpp"
#include <algorithm>
#include <cstring>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph::python {

namespace {
// FNV-1a over the bytes the spacing and neighbours depend on: a few ms at 1e5 particles.
std::uint64_t fingerprint(const PointCloud& c) {
  std::uint64_t h = 1469598103934665603ULL;
  const auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ p[k]) * 1099511628211ULL;
  };
  mix(&c.dim, sizeof(c.dim));
  if (!c.positions.empty()) mix(c.positions.data(), c.positions.size() * sizeof(Vec3));
  if (!c.tags.empty()) mix(c.tags.data(), c.tags.size() * sizeof(Tag));
  if (!c.normals.empty()) mix(c.normals.data(), c.normals.size() * sizeof(Vec3));
  return h;
}
}  // namespace

const PointCloud& as_cloud(const py::object& self) {
  check<ConfigError>(py::isinstance<PointCloud>(self), "cloud must be a vrsph.Cloud (vrsph.cloud.from_arrays, "
                     "vrsph.read_cloud, ...), got ", std::string(py::str(py::type::of(self).attr("__name__"))));
  return self.cast<const PointCloud&>();
}

CloudCache& cloud_cache(const py::object& self) {
  const auto& cloud = as_cloud(self);
  const std::uint64_t now = fingerprint(cloud);
  if (!py::hasattr(self, "_vrsph_cache")) {
    auto* cache = new CloudCache;
    cache->fingerprint = now;
    self.attr("_vrsph_cache") = py::capsule(cache, [](void* p) { delete static_cast<CloudCache*>(p); });
  }
  auto* cache = static_cast<CloudCache*>(self.attr("_vrsph_cache").cast<py::capsule>().get_pointer());
  check<InputError>(cache->fingerprint == now,
                    "the cloud's positions, tags or normals changed after vrsph cached its spacing and neighbours: "
                    "make a new Cloud (vrsph.cloud.from_arrays) for the moved particles");
  return *cache;
}

Real cached_spacing(const py::object& self) {
  CloudCache& cache = cloud_cache(self);
  if (cache.spacing < 0) {
    const auto& cloud = as_cloud(self);
    Real s = 0;
    {
      py::gil_scoped_release release;
      s = estimate_spacing(cloud);
    }
    cache.spacing = s;
  }
  return cache.spacing;
}

std::shared_ptr<const NeighbourList> cached_neighbours(const py::object& self, Real radius) {
  CloudCache& cache = cloud_cache(self);
  const auto it = cache.neighbours.find(radius);
  if (it != cache.neighbours.end()) return it->second;
  const auto& cloud = as_cloud(self);
  std::shared_ptr<const NeighbourList> nl;
  {
    py::gil_scoped_release release;
    SearchParams sp;
    sp.radius = radius;
    nl = std::make_shared<const NeighbourList>(find_neighbours(cloud, sp));
  }
  if (cache.recent.size() == 2) {
    cache.neighbours.erase(cache.recent.front());
    cache.recent.erase(cache.recent.begin());
  }
  cache.neighbours[radius] = nl;
  cache.recent.push_back(radius);
  return nl;
}

}  // namespace vrsph::python
