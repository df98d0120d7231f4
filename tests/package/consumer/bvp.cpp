// SPDX-License-Identifier: BSD-3-Clause
// The whole library workflow of a user with their own particles: a disk cloud built from
// arrays, div(grad u) = f with Dirichlet data, one solve() call, the field written for
// ParaView. u = exp(x) sin(y) is harmonic, so f = 0; the error must be small.
#include <cmath>
#include <iostream>
#include <vrsph/vrsph.hpp>

int main() {
  using namespace vrsph;
  BoundaryValueProblem p;
  p.cloud.dim = 2;
  const double dx = 0.05, pi = std::acos(-1.0);
  for (double x = -1; x <= 1; x += dx)  // interior: a lattice at least dx/2 inside the unit circle
    for (double y = -1; y <= 1; y += dx)
      if (std::hypot(x, y) < 1 - dx / 2) p.cloud.add({x, y, 0}, Tag::Interior);
  for (int k = 0; k < 126; ++k) {  // boundary: the circle at about dx, outward normals
    const Vec3 n(std::cos(2 * pi * k / 126), std::sin(2 * pi * k / 126), 0);
    p.cloud.add(n, Tag::Dirichlet);
  }
  const auto exact = [](const Vec3& x) { return std::exp(x[0]) * std::sin(x[1]); };
  p.f = Field::Zero(p.cloud.size());
  p.g = Field(p.cloud.size());
  for (Index i = 0; i < p.cloud.size(); ++i) p.g[i] = exact(p.cloud.positions[static_cast<std::size_t>(i)]);
  const BvpSolution s = solve(p, {.method = "vrsph"});
  double err = 0;
  for (Index i = 0; i < p.cloud.size(); ++i) err = std::max(err, std::abs(s.u[i] - p.g[i]));
  write_vtu("disk.vtu", p.cloud, {{"u", s.u}});
  std::cout << "disk: " << p.cloud.size() << " particles, max error " << err << ", M-matrix " << s.m_matrix << "\n";
  return err < 1e-3 && s.m_matrix ? 0 : 1;
}
