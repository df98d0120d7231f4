// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <numbers>
#include <vector>
#include <vrsph/analysis/compatibility.hpp>
#include <vrsph/core/error.hpp>
#include "../core/quadrature.hpp"

namespace vrsph {

namespace {
struct Rule {
  std::vector<Real> x, w;  // on [0, 1]
};

Rule gauss_legendre_unit(int n) {
  const detail::QuadratureRule g = detail::gauss_legendre(n);
  Rule r;
  for (std::size_t i = 0; i < g.x.size(); ++i) {
    r.x.push_back(0.5 * (1 + g.x[i]));
    r.w.push_back(0.5 * g.w[i]);
  }
  return r;
}

struct Sums {
  Real flux = 0, source = 0, abs = 0;
};

// Tensor rule over the box and each of its 2d faces.
Sums box_sums(const Domain& d, const Rule& g, const std::function<Real(const Vec3&)>& f,
              const std::function<Real(const Vec3&, const Vec3&)>& q) {
  Sums s;
  const int dim = d.dim;
  const Vec3 len = d.hi - d.lo;
  const auto n = static_cast<int>(g.x.size());
  // Volume: n^dim points.
  const int total = static_cast<int>(std::pow(n, dim));
  Real measure = 1;
  for (int k = 0; k < dim; ++k) measure *= len[k];
  for (int idx = 0; idx < total; ++idx) {
    Vec3 x = Vec3::Zero();
    Real w = measure;
    for (int k = 0, r = idx; k < dim; ++k, r /= n) {
      x[k] = d.lo[k] + len[k] * g.x[static_cast<std::size_t>(r % n)];
      w *= g.w[static_cast<std::size_t>(r % n)];
    }
    const Real v = f(x);
    s.source += w * v;
    s.abs += w * std::abs(v);
  }
  // Faces: axis k at lo (normal -e_k) and hi (+e_k); n^(dim-1) points each.
  const int face_total = static_cast<int>(std::pow(n, dim - 1));
  for (int k = 0; k < dim; ++k)
    for (int side = 0; side < 2; ++side) {
      Vec3 normal = Vec3::Zero();
      normal[k] = side ? 1 : -1;
      Real area = 1;
      for (int m = 0; m < dim; ++m)
        if (m != k) area *= len[m];
      for (int idx = 0; idx < face_total; ++idx) {
        Vec3 x = Vec3::Zero();
        x[k] = side ? d.hi[k] : d.lo[k];
        Real w = area;
        for (int m = 0, r = idx; m < dim; ++m) {
          if (m == k) continue;
          x[m] = d.lo[m] + len[m] * g.x[static_cast<std::size_t>(r % n)];
          w *= g.w[static_cast<std::size_t>(r % n)];
          r /= n;
        }
        const Real v = q(x, normal);
        s.flux += w * v;
        s.abs += w * std::abs(v);
      }
    }
  return s;
}

// Ball: Gauss–Legendre in the radius (and in cos θ in 3D), the periodic trapezoidal
// rule (spectrally accurate) in the azimuth.
Sums ball_sums(const Domain& d, const Rule& g, const std::function<Real(const Vec3&)>& f,
               const std::function<Real(const Vec3&, const Vec3&)>& q) {
  Sums s;
  const Real R = d.radius;
  const auto n = g.x.size();
  const std::size_t nphi = 4 * n;
  const auto add_volume = [&](const Vec3& x, Real w) {
    const Real v = f(x);
    s.source += w * v;
    s.abs += w * std::abs(v);
  };
  const auto add_surface = [&](const Vec3& unit, Real w) {
    const Real v = q(d.centre + R * unit, unit);
    s.flux += w * v;
    s.abs += w * std::abs(v);
  };
  if (d.dim == 1) {
    for (std::size_t i = 0; i < n; ++i) add_volume(d.centre + Vec3(R * (2 * g.x[i] - 1), 0, 0), 2 * R * g.w[i]);
    add_surface(Vec3(-1, 0, 0), 1);
    add_surface(Vec3(1, 0, 0), 1);
    return s;
  }
  const Real dphi = 2 * std::numbers::pi / static_cast<Real>(nphi);
  if (d.dim == 2) {
    for (std::size_t p = 0; p < nphi; ++p) {
      const Vec3 e(std::cos(static_cast<Real>(p) * dphi), std::sin(static_cast<Real>(p) * dphi), 0);
      for (std::size_t i = 0; i < n; ++i) add_volume(d.centre + R * g.x[i] * e, R * R * g.x[i] * g.w[i] * dphi);
      add_surface(e, R * dphi);
    }
    return s;
  }
  for (std::size_t p = 0; p < nphi; ++p)
    for (std::size_t j = 0; j < n; ++j) {
      const Real c = 2 * g.x[j] - 1, sn = std::sqrt(std::max(0.0, 1 - c * c));
      const Vec3 e(sn * std::cos(static_cast<Real>(p) * dphi), sn * std::sin(static_cast<Real>(p) * dphi), c);
      const Real wa = 2 * g.w[j] * dphi;  // d(cos θ) dφ
      for (std::size_t i = 0; i < n; ++i) add_volume(d.centre + R * g.x[i] * e, R * R * R * g.x[i] * g.x[i] * g.w[i] * wa);
      add_surface(e, R * R * wa);
    }
  return s;
}

Sums sums(const Domain& d, int order, const std::function<Real(const Vec3&)>& f,
          const std::function<Real(const Vec3&, const Vec3&)>& q) {
  const Rule g = gauss_legendre_unit(order);
  if (d.shape == Domain::Shape::Box) return box_sums(d, g, f, q);
  return ball_sums(d, g, f, q);
}
}  // namespace

bool NeumannBalance::compatible() const {
  return std::abs(flux - source) <= std::max(1e-8 * scale, 10 * quadrature_error);
}

NeumannBalance neumann_balance(const Domain& domain, const std::function<Real(const Vec3&)>& f,
                               const std::function<Real(const Vec3&, const Vec3&)>& q) {
  check<ConfigError>(domain.shape != Domain::Shape::None && domain.dim >= 1 && domain.dim <= 3,
                     "the Neumann compatibility check needs a box or ball domain");
  const int low = domain.dim == 3 ? 12 : 20, high = domain.dim == 3 ? 24 : 40;
  const Sums a = sums(domain, low, f, q), b = sums(domain, high, f, q);
  NeumannBalance nb;
  nb.flux = b.flux;
  nb.source = b.source;
  nb.scale = b.abs;
  nb.quadrature_error = std::abs((a.flux - a.source) - (b.flux - b.source));
  return nb;
}

}  // namespace vrsph
