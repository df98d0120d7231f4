// SPDX-License-Identifier: BSD-3-Clause
// Moving least-squares values at arbitrary points (point_sampling.hpp).
#include <cmath>
#include <Eigen/QR>
#include <vrsph/analysis/point_sampling.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

namespace {
// The monomials of degree <= 2 in the scaled offset s (|s| <= 1): 1, s_a, s_a s_b (a <= b).
int quadratic_terms(int d) { return 1 + d + d * (d + 1) / 2; }
void quadratic_basis(const Vec3& s, int d, Eigen::MatrixXd::RowXpr row) {
  int k = 0;
  row[k++] = 1;
  for (int a = 0; a < d; ++a) row[k++] = s[a];
  for (int a = 0; a < d; ++a)
    for (int b = a; b < d; ++b) row[k++] = s[a] * s[b];
}
// Wendland's C2 function of q = r / radius in [0, 1].
Real wendland_c2(Real q) { return std::pow(1 - q, 4) * (1 + 4 * q); }
}  // namespace

Eigen::MatrixXd sample_field(const PointCloud& cloud, const Eigen::MatrixXd& values, std::span<const Vec3> points,
                             Real radius) {
  const int d = cloud.dim;
  const Index n = cloud.size();
  check<InputError>(values.rows() == n, "sampling: ", values.rows(), " rows of values for ", n, " particles");
  check<InputError>(values.allFinite(), "sampling: the field is not finite");
  check<ConfigError>(std::isfinite(radius) && radius > 0, "sampling: the radius must be positive, got ", radius);
  const int terms = quadratic_terms(d);
  const Domain& box = cloud.domain;
  Eigen::MatrixXd out(static_cast<Index>(points.size()), values.cols());
  std::vector<Index> near;
  std::vector<Real> weight;
  std::vector<Vec3> offset;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Vec3& x = points[p];
    check<InputError>(x.head(d).allFinite(), "sampling: point ", p, " is not finite");
    near.clear();
    weight.clear();
    offset.clear();
    for (Index j = 0; j < n; ++j) {
      Vec3 r = cloud.positions[static_cast<std::size_t>(j)] - x;
      for (int a = 0; a < d; ++a)
        if (box.shape == Domain::Shape::Box && box.periodic[static_cast<std::size_t>(a)])
          r[a] -= box.period(a) * std::round(r[a] / box.period(a));
      for (int a = d; a < 3; ++a) r[a] = 0;  // a query point's unused coordinates are not read
      const Real dist = r.norm();
      if (dist >= radius) continue;
      near.push_back(j);
      weight.push_back(std::sqrt(wendland_c2(dist / radius)));
      offset.push_back(r / radius);
    }
    check<GeometryError>(static_cast<int>(near.size()) >= terms, "sampling: point ", p, " (", x[0], ", ", x[1],
                         d == 3 ? detail::concat(", ", x[2]) : std::string(), ") has ", near.size(),
                         " particles within the radius ", radius, "; a quadratic fit needs ", terms);
    Eigen::MatrixXd P(static_cast<Index>(near.size()), terms);
    Eigen::MatrixXd b(static_cast<Index>(near.size()), values.cols());
    for (std::size_t k = 0; k < near.size(); ++k) {
      quadratic_basis(offset[k], d, P.row(static_cast<Index>(k)));
      P.row(static_cast<Index>(k)) *= weight[k];
      b.row(static_cast<Index>(k)) = weight[k] * values.row(near[k]);
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(P);
    check<GeometryError>(qr.rank() == terms, "sampling: the particles near point ", p,
                         " do not determine a quadratic (rank ", qr.rank(), " of ", terms, ")");
    out.row(static_cast<Index>(p)) = qr.solve(b).row(0);  // the constant term: the value at x
  }
  return out;
}

}  // namespace vrsph
