// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <unordered_map>
#include <vrsph/reproduce/spe_problems.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

namespace {
constexpr Real pi = std::numbers::pi;
constexpr Real boundary_tol = 1e-12;

// sin(nθ) for n = n0, n0 + s, n0 + 2s, ... by sin((n+s)θ) = 2 cos(sθ) sin(nθ) - sin((n-s)θ).
struct SineRecurrence {
  Real prev, cur, two_cos;
  SineRecurrence(Real theta, Real n0, Real step)
      : prev(std::sin((n0 - step) * theta)), cur(std::sin(n0 * theta)), two_cos(2 * std::cos(step * theta)) {}
  Real next() {
    const Real out = cur;
    const Real nxt = two_cos * cur - prev;
    prev = cur;
    cur = nxt;
    return out;
  }
};
// The sides of the unit square a point lies on, in ψ order: y = 0, x = 1, y = 1, x = 0.
std::array<bool, 4> sides_of(const Vec3& p) {
  return {std::abs(p[1]) < boundary_tol, std::abs(p[0] - 1) < boundary_tol, std::abs(p[1] - 1) < boundary_tol,
          std::abs(p[0]) < boundary_tol};
}
}  // namespace

Real spe_dirichlet_solution(const Vec3& p, const SpeBoundaryData& d, int terms) {
  const Real x = p[0], y = p[1];
  // sinh(nπt)/sinh(nπ) = e^{-nπ(1-t)} (1 - e^{-2nπt}) / (1 - e^{-2nπ}) for t = 1-y, y, x, 1-x.
  const std::array<Real, 4> t{1 - y, x, y, 1 - x};  // ψ1, ψ2, ψ3, ψ4
  std::array<Real, 4> decay{}, decay_step{}, twin{}, twin_step{};
  for (std::size_t k = 0; k < 4; ++k) {
    decay[k] = std::exp(-pi * (1 - t[k]));  // n = 1
    decay_step[k] = std::exp(-2 * pi * (1 - t[k]));
    twin[k] = std::exp(-2 * pi * t[k]);
    twin_step[k] = std::exp(-4 * pi * t[k]);
  }
  SineRecurrence sx(pi * x, 1, 2), sy(pi * y, 1, 2);
  Real sum = 0, den = std::exp(-2 * pi);
  const Real den_step = std::exp(-4 * pi);
  for (int m = 0; m < terms; ++m) {
    const Real n = 2 * m + 1;
    const Real sinx = sx.next(), siny = sy.next();
    const Real inv = 1 / (1 - den);
    Real term = 0;
    Real largest = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const Real ratio = decay[k] * (1 - twin[k]) * inv;
      term += d.psi[k] * (k == 0 || k == 2 ? sinx : siny) * ratio;
      largest = std::max(largest, decay[k]);
      decay[k] *= decay_step[k];
      twin[k] *= twin_step[k];
    }
    sum += 4 / (n * pi) * term;
    den *= den_step;
    if (largest < 1e-17) break;
  }
  return sum;
}

Real spe_dirichlet_boundary(const Vec3& p, const SpeBoundaryData& d) {
  const auto on = sides_of(p);
  Real sum = 0;
  int sides = 0;
  for (std::size_t k = 0; k < 4; ++k)
    if (on[k]) {
      sum += d.psi[k];
      ++sides;
    }
  return sides ? sum / sides : spe_dirichlet_solution(p, d);
}

Real spe_mixed_solution(const Vec3& p, const SpeBoundaryData& d, int terms) {
  const Real x = p[0], y = p[1];
  // λ_n = (2n-1)π/2; cosh(λx)/sinh(λ) = e^{-λ(1-x)} (1 + e^{-2λx}) / (1 - e^{-2λ}).
  Real a = std::exp(-0.5 * pi * (1 - x)), a_step = std::exp(-pi * (1 - x));        // e^{-λ(1-x)}
  Real b = std::exp(-0.5 * pi * x), b_step = std::exp(-pi * x);                    // e^{-λx}
  Real ta = std::exp(-pi * x), ta_step = std::exp(-2 * pi * x);                    // e^{-2λx}
  Real tb = std::exp(-pi * (1 - x)), tb_step = std::exp(-2 * pi * (1 - x));        // e^{-2λ(1-x)}
  Real den = std::exp(-pi), den_step = std::exp(-2 * pi);                          // e^{-2λ}
  SineRecurrence sy(0.5 * pi * y, 1, 2);
  Real sum = 0;
  for (int n = 1; n <= terms; ++n) {
    const Real lambda = (2 * n - 1) * pi / 2;
    const Real s = sy.next();
    const Real inv = 1 / (1 - den);
    const Real ch_x = a * (1 + ta) * inv, ch_1mx = b * (1 + tb) * inv;
    sum += (2 * d.psi[1] * ch_x + 2 * d.psi[3] * ch_1mx) / (lambda * lambda) * s;
    a *= a_step;
    b *= b_step;
    ta *= ta_step;
    tb *= tb_step;
    den *= den_step;
    if (a < 1e-17 && b < 1e-17) break;
  }
  return d.psi[0] + d.psi[2] * y + sum;
}

Real spe_mixed_flux(const Vec3& p, const SpeBoundaryData& d) {
  const auto on = sides_of(p);
  Real sum = 0;
  int sides = 0;
  for (std::size_t k = 1; k < 4; ++k)  // the Neumann sides x = 1, y = 1, x = 0
    if (on[k]) {
      sum += d.psi[k];
      ++sides;
    }
  check<InputError>(sides > 0, "spe-mixed: flux requested off the Neumann sides at (", p[0], ", ", p[1], ")");
  return sides == 1 ? sum : sum / std::sqrt(2.0);
}

Real spe_plate_velocity(Real y, Real t) {
  // At t = 0 the series is the Fourier series of the parabola: v = 0, but it converges like
  // n^-3 (10^5 terms per point); the start value is exact without it.
  if (t <= 0) return 0;
  Real sum = 0;
  for (int n = 0; n < 100000; ++n) {
    const Real k = (2 * n + 1) * pi / 2;
    const Real decay = std::exp(-k * k * t);
    const Real term = (n % 2 ? -1.0 : 1.0) / ((2.0 * n + 1) * (2.0 * n + 1) * (2.0 * n + 1)) * std::cos(k * y) * decay;
    sum += term;
    if (decay / ((2.0 * n + 1) * (2.0 * n + 1) * (2.0 * n + 1)) < 1e-18) break;
  }
  return 0.5 * (1 - y * y) - 16 / (pi * pi * pi) * sum;
}

DiffusionProblem spe_plate_problem(Real dx) {
  check<ConfigError>(std::isfinite(dx) && dx > 0 && dx <= 0.5, "plate flow: spacing dx must be in (0, 0.5], got ", dx);
  const Real intervals = 2 / dx;
  check<ConfigError>(std::abs(intervals - std::round(intervals)) < 1e-9 * intervals && intervals <= 4000,
                     "plate flow: dx must divide the side 2 (2/dx an integer up to 4000), got dx = ", dx);
  Domain box = Domain::unit_box(2);
  box.lo = Vec3(0, -1, 0);
  box.hi = Vec3(2, 1, 0);
  DiffusionProblem p;
  p.cloud = vertex_lattice(box, static_cast<int>(std::round(intervals)));
  p.u0 = Field::Zero(p.cloud.size());
  p.source = [](const Vec3&, Real) { return 1.0; };
  // The profile depends on y only and the lattice has 2/dx + 1 rows: the series is summed
  // once per row and time (it was most of a 10^5-particle run's time when summed per particle).
  struct Memo {
    std::mutex lock;
    Real t = std::nan("");
    std::unordered_map<Real, Real> by_y;
  };
  auto memo = std::make_shared<Memo>();
  p.boundary = [memo](const Vec3& x, Real t) {
    const std::lock_guard<std::mutex> guard(memo->lock);
    if (!(memo->t == t)) {
      memo->t = t;
      memo->by_y.clear();
    }
    const auto [it, fresh] = memo->by_y.try_emplace(x[1], 0.0);
    if (fresh) it->second = spe_plate_velocity(x[1], t);
    return it->second;
  };
  p.exact = p.boundary;
  return p;
}

const std::array<std::array<Real, 4>, 10>& spe_plate_table1() {
  static const std::array<std::array<Real, 4>, 10> t{{{-3.790, -4.099, -3.699, -3.608},
                                                      {-4.825, -5.137, -4.738, -3.296},
                                                      {-5.894, -6.206, -5.807, -2.098},
                                                      {-6.965, -7.277, -6.878, -0.900},
                                                      {-8.037, -8.349, -7.950, 0.298},
                                                      {-9.108, -9.420, -9.021, 1.496},
                                                      {-10.180, -10.491, -10.092, 2.693},
                                                      {-11.256, -11.554, -11.161, 3.891},
                                                      {-12.379, -12.539, -12.195, 5.089},
                                                      {-12.975, -13.019, -12.922, 6.287}}};
  return t;
}

namespace {
class SpeFunction final : public ScalarFunction {
 public:
  SpeFunction(std::string which, SpeBoundaryData data) : which_(std::move(which)), data_(data) { dim = 2; }
  std::string name() const override { return which_; }
  Real value(const Vec3& x) const override {
    if (which_ == "spe-dirichlet") return spe_dirichlet_solution(x, data_);
    if (which_ == "spe-dirichlet-boundary") return spe_dirichlet_boundary(x, data_);
    return spe_mixed_solution(x, data_);
  }
  std::unique_ptr<ScalarFunction> clone() const override {
    auto copy = std::make_unique<SpeFunction>(which_, data_);
    copy->length_scale = length_scale;
    return copy;
  }

 private:
  std::string which_;
  SpeBoundaryData data_;
};
}  // namespace

std::unique_ptr<ScalarFunction> make_spe_function(const std::string& which, const SpeBoundaryData& data) {
  check<ConfigError>(which == "spe-dirichlet" || which == "spe-dirichlet-boundary" || which == "spe-mixed",
                     "unknown [SPE] function '", which, "'");
  return std::make_unique<SpeFunction>(which, data);
}

}  // namespace vrsph
