// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vrsph/cloud/domain.hpp>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

Domain Domain::box(int dim, const Vec3& lo, const Vec3& hi) {
  check<InputError>(dim >= 1 && dim <= 3, "domain dimension must be 1, 2 or 3, got ", dim);
  Domain d;
  d.shape = Shape::Box;
  d.dim = dim;
  d.lo = Vec3::Zero();
  d.hi = Vec3::Zero();
  for (int k = 0; k < dim; ++k) {
    check<InputError>(hi[k] > lo[k], "box: upper bound ", hi[k], " must exceed lower bound ", lo[k],
                      " in coordinate ", k);
    d.lo[k] = lo[k];
    d.hi[k] = hi[k];
  }
  return d;
}

Domain Domain::periodic_box(int dim, const Vec3& lo, const Vec3& hi, const std::string& axes) {
  check<InputError>(dim >= 1 && dim <= 3, "domain dimension must be 1, 2 or 3, got ", dim);
  Real volume = 1;
  for (int k = 0; k < dim; ++k) {
    check<InputError>(std::isfinite(lo[k]) && std::isfinite(hi[k]) && std::isfinite(hi[k] - lo[k]), "periodic box: the side along ",
                      "xyz"[k], " (", lo[k], " .. ", hi[k], ") is not a finite length");
    check<InputError>(hi[k] > lo[k], "periodic box: the upper corner must exceed the lower one along ", "xyz"[k], " (",
                      lo[k], " .. ", hi[k], ")");
    // As for the particles themselves (validate): beyond that, spacings and volumes overflow.
    check<InputError>(std::max(std::abs(lo[k]), std::abs(hi[k])) <= max_coordinate, "periodic box: the corner along ",
                      "xyz"[k], " (", lo[k], " .. ", hi[k], ") is beyond +-", max_coordinate, " (rescale the cloud)");
    volume *= hi[k] - lo[k];
  }
  Domain d = box(dim, lo, hi);
  check<InputError>(std::isfinite(volume), "periodic box: its volume overflows a double (rescale the cloud)");
  d.set_periodic(axes);
  return d;
}

Domain Domain::unit_box(int dim) { return box(dim, Vec3::Zero(), Vec3::Ones()); }

Domain Domain::symmetric_box(int dim, Real half_width) {
  return box(dim, Vec3::Constant(-half_width), Vec3::Constant(half_width));
}

Domain Domain::ball(int dim, const Vec3& centre, Real radius) {
  check<InputError>(dim >= 1 && dim <= 3, "domain dimension must be 1, 2 or 3, got ", dim);
  check<InputError>(radius > 0, "ball radius must be positive, got ", radius);
  Domain d;
  d.shape = Shape::Ball;
  d.dim = dim;
  d.centre = Vec3::Zero();
  for (int k = 0; k < dim; ++k) d.centre[k] = centre[k];
  d.radius = radius;
  return d;
}

Real Domain::signed_distance(const Vec3& x) const {
  switch (shape) {
    case Shape::None:
      return std::numeric_limits<Real>::infinity();
    case Shape::Ball:
      return radius - (x - centre).head(dim).norm();
    case Shape::Box: {
      // Inside: distance to the nearest face. Outside: minus the Euclidean distance to the box.
      Real inside = std::numeric_limits<Real>::infinity();
      Real outside2 = 0;
      for (int k = 0; k < dim; ++k) {
        if (periodic[static_cast<std::size_t>(k)]) continue;
        inside = std::min({inside, x[k] - lo[k], hi[k] - x[k]});
        const Real excess = std::max({lo[k] - x[k], x[k] - hi[k], Real(0)});
        outside2 += excess * excess;
      }
      return inside >= 0 ? inside : -std::sqrt(outside2);
    }
  }
  return 0;
}

Real Domain::measure() const {
  switch (shape) {
    case Shape::None:
      return 0;
    case Shape::Box: {
      Real m = 1;
      for (int k = 0; k < dim; ++k) m *= hi[k] - lo[k];
      return m;
    }
    case Shape::Ball:
      if (dim == 1) return 2 * radius;
      if (dim == 2) return std::numbers::pi * radius * radius;
      return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  }
  return 0;
}

Vec3 Domain::outward_normal(const Vec3& x, Real tol) const {
  Vec3 n = Vec3::Zero();
  if (shape == Shape::Ball) {
    n.head(dim) = (x - centre).head(dim);
    const Real len = n.norm();
    return len > 0 ? Vec3(n / len) : n;
  }
  if (shape != Shape::Box) return n;
  const Real d = std::abs(signed_distance(x));
  for (int k = 0; k < dim; ++k) {
    if (periodic[static_cast<std::size_t>(k)]) continue;
    if (std::abs(x[k] - lo[k]) <= d + tol) n[k] -= 1;
    if (std::abs(hi[k] - x[k]) <= d + tol) n[k] += 1;
  }
  const Real len = n.norm();
  return len > 0 ? Vec3(n / len) : n;
}

bool Domain::any_periodic() const {
  return shape == Shape::Box && (periodic[0] || periodic[1] || periodic[2]);
}

Real Domain::shortest_period() const {
  Real shortest = std::numeric_limits<Real>::infinity();
  if (shape != Shape::Box) return shortest;
  for (int k = 0; k < dim; ++k)
    if (periodic[static_cast<std::size_t>(k)]) shortest = std::min(shortest, period(k));
  return shortest;
}

bool Domain::fully_periodic() const {
  if (shape != Shape::Box) return false;
  for (int k = 0; k < dim; ++k)
    if (!periodic[static_cast<std::size_t>(k)]) return false;
  return true;
}

Vec3 Domain::wrap(const Vec3& x) const {
  Vec3 y = x;
  for (int k = 0; k < dim; ++k) {
    if (!periodic[static_cast<std::size_t>(k)]) continue;
    const Real L = period(k);
    y[k] = lo[k] + (x[k] - lo[k]) - L * std::floor((x[k] - lo[k]) / L);
    if (y[k] >= hi[k]) y[k] = lo[k];  // round-off of a point just below lo
  }
  return y;
}

void Domain::set_periodic(const std::string& axes) {
  periodic = {false, false, false};
  if (axes.empty() || axes == "none") return;
  check<InputError>(shape == Shape::Box, "periodic axes need a box domain");
  std::size_t start = 0;
  while (start <= axes.size()) {
    const std::size_t comma = std::min(axes.find(',', start), axes.size());
    const std::string a = axes.substr(start, comma - start);
    if (a == "all") {
      for (int k = 0; k < dim; ++k) periodic[static_cast<std::size_t>(k)] = true;
    } else {
      const int k = a == "x" ? 0 : a == "y" ? 1 : a == "z" ? 2 : -1;
      check<ConfigError>(k >= 0, "periodic axes are x, y, z or all (comma-separated), got '", a, "'");
      check<ConfigError>(k < dim, "periodic axis ", a, " does not exist in ", dim, "D");
      periodic[static_cast<std::size_t>(k)] = true;
    }
    start = comma + 1;
  }
}

std::string Domain::periodic_axes() const {
  std::string out;
  for (int k = 0; k < 3; ++k)
    if (periodic[static_cast<std::size_t>(k)]) out += std::string(out.empty() ? "" : ",") + "xyz"[k];
  return out;
}

}  // namespace vrsph
