// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/reference_weight.hpp>

namespace vrsph {

namespace {

using Piece = ReferenceWeight::Piece;

Real horner(const std::vector<Real>& c, Real r) {
  Real v = 0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) v = v * r + *it;
  return v;
}

std::vector<Real> derivative_of(const std::vector<Real>& c) {
  std::vector<Real> d;
  for (std::size_t k = 1; k < c.size(); ++k) d.push_back(static_cast<Real>(k) * c[k]);
  return d;
}

// ∫_a^b r^s p(r) dr for p = Σ c_k r^k.
Real integral(const std::vector<Real>& c, Real a, Real b, int s) {
  Real v = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const int e = s + static_cast<int>(k) + 1;
    v += c[k] * (std::pow(b, e) - std::pow(a, e)) / e;
  }
  return v;
}

void check_dim(int dim) { check<ConfigError>(dim >= 1 && dim <= 3, "reference weight: dimension must be 1, 2 or 3, got ", dim); }

// Scales the pieces so that |S^(d-1)| ∫_0^1 r^(d-1) w = 1.
std::vector<Piece> normalised(std::vector<Piece> pieces, int dim) {
  Real m = 0;
  for (const auto& p : pieces) m += integral(p.c, p.from, p.to, dim - 1);
  const Real scale = 1 / (unit_sphere_area(dim) * m);
  for (auto& p : pieces)
    for (Real& c : p.c) c *= scale;
  return pieces;
}

// -(1/d) r w'(r), piece by piece: the gradient/Laplacian weight of an interpolant (normalised
// when w is, by parts).
std::vector<Piece> minus_r_derivative_over_d(const std::vector<Piece>& w, int dim) {
  std::vector<Piece> out;
  for (const auto& p : w) {
    const std::vector<Real> d = derivative_of(p.c);
    Piece q{p.from, p.to, std::vector<Real>(d.size() + 1, 0.0)};
    for (std::size_t k = 0; k < d.size(); ++k) q.c[k + 1] = -d[k] / dim;
    out.push_back(q);
  }
  return out;
}

std::vector<Piece> cubic_spline() {  // §2.1: 1 - 6r² + 6r³ on [0, 1/2), 2(1 - r)³ on [1/2, 1)
  return {{0, 0.5, {1, 0, -6, 6}}, {0.5, 1, {2, -6, 6, -2}}};
}

// r^q times the polynomial Σ b_k r^k.
std::vector<Piece> monomial_times(int q, std::vector<Real> b) {
  b.insert(b.begin(), static_cast<std::size_t>(q), 0.0);
  return {{0, 1, b}};
}

}  // namespace

Real unit_sphere_area(int dim) {
  check_dim(dim);
  return dim == 1 ? 2 : dim == 2 ? 2 * std::numbers::pi : 4 * std::numbers::pi;
}

ReferenceWeight::ReferenceWeight(std::string name, int dim, std::vector<Piece> pieces)
    : name_(std::move(name)), dim_(dim), pieces_(std::move(pieces)) {
  check_dim(dim);
  check<ConfigError>(!pieces_.empty(), "reference weight ", name_, ": no polynomial piece");
}

Real ReferenceWeight::value(Real r) const {
  for (const auto& p : pieces_)
    if (r >= p.from && r < p.to) return horner(p.c, r);
  return 0;
}

Real ReferenceWeight::derivative(Real r) const {
  for (const auto& p : pieces_)
    if (r >= p.from && r < p.to) return horner(derivative_of(p.c), r);
  return 0;
}

Real ReferenceWeight::value(Real r, Real h) const { return std::pow(h, -dim_) * value(r / h); }

Real ReferenceWeight::radial_moment(int m) const {
  Real v = 0;
  for (const auto& p : pieces_) v += integral(p.c, p.from, p.to, dim_ - 1 + m);
  return v;
}

int ReferenceWeight::hypothesis1_order() const {
  int n = 1;
  for (int j = 1; j <= 7; ++j) {
    Real scale = 0;  // ∫ r^(d-1+2j) |w|, by the pieces' absolute coefficients (an upper bound)
    for (const auto& p : pieces_) {
      std::vector<Real> a(p.c.size());
      for (std::size_t k = 0; k < a.size(); ++k) a[k] = std::abs(p.c[k]);
      scale += integral(a, p.from, p.to, dim_ - 1 + 2 * j);
    }
    if (std::abs(radial_moment(2 * j)) > 1e-12 * scale) break;
    n = 2 * j + 1;
  }
  return n;
}

int ReferenceWeight::hypothesis2_order() const {
  const auto& c = pieces_.front().c;
  for (std::size_t k = 0; k < c.size(); ++k)
    if (c[k] != 0) return static_cast<int>(k) - 1;
  return -1;
}

std::vector<std::string> reference_weight_names() {
  return {"pi1", "pi2", "pi3", "grad1", "grad2", "grad3", "delta1", "delta2", "delta3"};
}

WeightOperator reference_weight_operator(const std::string& name) {
  if (name.rfind("pi", 0) == 0) return WeightOperator::Interpolant;
  if (name.rfind("grad", 0) == 0) return WeightOperator::Gradient;
  if (name.rfind("delta", 0) == 0) return WeightOperator::Laplacian;
  throw ConfigError("'" + name + "' is not a reference weight name (pi*, grad* or delta*)");
}

ReferenceWeight reference_weight(const std::string& name, int dim) {
  check_dim(dim);
  std::vector<Piece> p;
  if (name == "pi1") p = normalised(monomial_times(0, {1, -1}), dim);
  else if (name == "pi2") p = normalised(cubic_spline(), dim);
  else if (name == "pi3" || name == "grad3" || name == "delta3") {
    // The tabulated 2D polynomials (pi3 (1 - r)(2 - 3r), grad3 r(1 - r)(5 - 7r), delta3
    // r²(1 - r)(3 - 4r)) are App. C's n = 3 weights of 2D; renormalised in 1D or 3D they would
    // lose their vanishing second moment, so every dimension gets its own App. C weight.
    return ReferenceWeight(name, dim, construct_reference_weight(dim, reference_weight_operator(name), 3).pieces());
  }
  else if (name == "grad1") p = normalised(monomial_times(1, {1, -1}), dim);           // r(1 - r)
  else if (name == "grad2" || name == "delta2") p = minus_r_derivative_over_d(normalised(cubic_spline(), dim), dim);
  else if (name == "delta1") p = normalised(monomial_times(2, {1, -1}), dim);          // r²(1 - r)
  else {
    std::string known;
    for (const auto& n : reference_weight_names()) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError("unknown reference weight '" + name + "' (known: " + known + ")");
  }
  return ReferenceWeight(name, dim, std::move(p));
}

ReferenceWeight construct_reference_weight(int dim, WeightOperator op, int n, bool smooth_end) {
  check_dim(dim);
  check<ConfigError>(n >= 1 && n <= 15 && n % 2 == 1, "reference weight: Hypothesis 1 order n must be odd, 1..15, got ", n);
  const int q = op == WeightOperator::Interpolant ? 0 : op == WeightOperator::Gradient ? 1 : 2;
  const int moments = n / 2, p = 1 + moments + (smooth_end ? 1 : 0);
  // Unknowns a_1..a_p: (C1) 1 + Σ a = 0; (C2) 1/(d+q+2j) + Σ a_ℓ/(d+q+2j+ℓ) = 0; optional Σ ℓ a_ℓ = 0.
  Eigen::MatrixXd A(p, p);
  Eigen::VectorXd b(p);
  int row = 0;
  for (int l = 1; l <= p; ++l) A(row, l - 1) = 1;
  b[row++] = -1;
  for (int j = 1; j <= moments; ++j, ++row) {
    for (int l = 1; l <= p; ++l) A(row, l - 1) = 1.0 / (dim + q + 2 * j + l);
    b[row] = -1.0 / (dim + q + 2 * j);
  }
  if (smooth_end) {
    for (int l = 1; l <= p; ++l) A(row, l - 1) = l;
    b[row++] = 0;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  check<NumericalError>(lu.isInvertible(), "reference weight: the App. C system for n = ", n, " is singular");
  const Eigen::VectorXd a = lu.solve(b);
  std::vector<Real> poly{1};
  for (int l = 0; l < p; ++l) poly.push_back(a[l]);
  const char* kind = q == 0 ? "pi" : q == 1 ? "grad" : "delta";
  return ReferenceWeight(detail::concat(kind, "(n=", n, smooth_end ? ", smooth" : "", ")"), dim,
                         normalised(monomial_times(q, poly), dim));
}

}  // namespace vrsph
