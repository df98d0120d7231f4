// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <vrsph/cloud/box_faces.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

std::array<bool, 6> parse_box_faces(const std::vector<std::string>& faces, int dim) {
  std::array<bool, 6> on{};
  for (const auto& f : faces) {
    if (f == "all") {
      for (int k = 0; k < 2 * dim; ++k) on[static_cast<std::size_t>(k)] = true;
      continue;
    }
    const bool ok = f.size() == 2 && f[0] >= 'x' && f[0] <= 'z' && (f[1] == '0' || f[1] == '1') && f[0] - 'x' < dim;
    check<ConfigError>(ok, "unknown Neumann face '", f, "' (known: x0, x1", dim > 1 ? ", y0, y1" : "",
                       dim > 2 ? ", z0, z1" : "", ", all)");
    on[static_cast<std::size_t>(2 * (f[0] - 'x') + (f[1] - '0'))] = true;
  }
  return on;
}

Index retag_neumann_faces(PointCloud& cloud, const std::array<bool, 6>& on, Real dx) {
  if (std::none_of(on.begin(), on.end(), [](bool b) { return b; })) return 0;
  const Domain& box = cloud.domain;
  Index count = 0;
  if (!cloud.has_normals()) cloud.normals.assign(static_cast<std::size_t>(cloud.size()), Vec3::Zero());
  const Real tol = 1e-9 * dx;
  for (Index i = 0; i < cloud.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (cloud.tags[si] != Tag::Dirichlet) continue;
    const Vec3& x = cloud.positions[si];
    if (box.shape == Domain::Shape::Ball) {  // a curved boundary has one "face"
      if (on[0]) {
        cloud.tags[si] = Tag::Neumann;
        ++count;
      }
      continue;
    }
    Vec3 normal = Vec3::Zero();
    bool all_neumann = true, any = false;
    for (int k = 0; k < cloud.dim; ++k)
      for (int side = 0; side < 2; ++side) {
        const Real face = side == 0 ? box.lo[k] : box.hi[k];
        if (std::abs(x[k] - face) > tol) continue;
        any = true;
        all_neumann = all_neumann && on[static_cast<std::size_t>(2 * k + side)];
        normal[k] += side == 0 ? -1 : 1;
      }
    if (!any || !all_neumann) continue;
    cloud.tags[si] = Tag::Neumann;
    cloud.normals[si] = normal.normalized();
    ++count;
  }
  return count;
}

}  // namespace vrsph
