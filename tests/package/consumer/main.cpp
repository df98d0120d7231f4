// SPDX-License-Identifier: BSD-3-Clause
// A downstream program: SPH Laplacian of x^2 + y^2 on a lattice must be close to 4.
#include <cmath>
#include <iostream>
#include <vrsph/vrsph.hpp>

int main() {
  using namespace vrsph;
  PointCloud cloud = cell_centred_lattice(Domain::symmetric_box(2, 1.0), 16, false, 5);
  SearchParams sp;
  sp.radius = 3 * cloud.spacing;
  const NeighbourList nl = find_neighbours(cloud, sp);
  const auto method = builtin_methods().create("sph");
  const Stencil s = method->build({cloud, nl, KernelType::CubicSpline, cloud.spacing}, {OperatorKind::Laplacian});
  Field u(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) u[i] = cloud.positions[static_cast<std::size_t>(i)].squaredNorm();
  const Field lap = apply_component(s, u, 0);
  Index centre = 0;
  for (Index i = 0; i < cloud.size(); ++i)
    if (cloud.positions[static_cast<std::size_t>(i)].norm() < cloud.positions[static_cast<std::size_t>(centre)].norm()) centre = i;
  std::cout << "laplacian(x^2+y^2) at the centre = " << lap[centre] << "\n";
  return std::abs(lap[centre] - 4) < 0.1 ? 0 : 1;
}
