#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/moments.hpp>

namespace vrsph {

const std::vector<std::array<int, 3>>& moment_exponents(MomentConditions c, int dim) {
  static const auto table = [] {
    std::array<std::array<std::vector<std::array<int, 3>>, 3>, 2> t;
    for (int d = 1; d <= 3; ++d)
      for (int deg = 0; deg <= 2; ++deg)
        for (int a0 = deg; a0 >= 0; --a0)
          for (int a1 = deg - a0; a1 >= 0; --a1) {
            const std::array<int, 3> a{a0, a1, deg - a0 - a1};
            if ((d < 2 && a[1]) || (d < 3 && a[2])) continue;
            t[1][static_cast<std::size_t>(d - 1)].push_back(a);                 // Laplace: |alpha| <= 2
            if (deg >= 1) t[0][static_cast<std::size_t>(d - 1)].push_back(a);   // Gradient: 1 <= |alpha| <= 2
          }
    return t;
  }();
  check<ConfigError>(dim >= 1 && dim <= 3, "moment conditions: dimension must be 1, 2 or 3, got ", dim);
  return table[c == MomentConditions::Laplace ? 1 : 0][static_cast<std::size_t>(dim - 1)];
}

int moment_rows(MomentConditions c, int dim) { return dim * static_cast<int>(moment_exponents(c, dim).size()); }

void build_moment_system(MomentConditions c, int dim, const Vec3* xji, const Real* half_y, int n, Real* A, Real* b) {
  const auto& alphas = moment_exponents(c, dim);
  const int m = dim * static_cast<int>(alphas.size());
  for (int beta = 0; beta < dim; ++beta)
    for (std::size_t a = 0; a < alphas.size(); ++a) {
      const auto& al = alphas[a];
      b[static_cast<std::size_t>(beta) * alphas.size() + a] = (al[0] + al[1] + al[2] == 1 && al[static_cast<std::size_t>(beta)] == 1) ? 1.0 : 0.0;
    }
  for (int j = 0; j < n; ++j) {
    const Vec3& d = xji[j];
    // Monomials x_ji^alpha for this neighbour, then times (x_ji)_beta * Y/2.
    Real mono[10];
    for (std::size_t a = 0; a < alphas.size(); ++a) {
      Real p = 1;
      for (int k = 0; k < dim; ++k)
        for (int e = 0; e < alphas[a][static_cast<std::size_t>(k)]; ++e) p *= d[k];
      mono[a] = p;
    }
    Real* col = A + static_cast<std::size_t>(j) * static_cast<std::size_t>(m);
    for (int beta = 0; beta < dim; ++beta) {
      const Real s = half_y[j] * d[beta];
      for (std::size_t a = 0; a < alphas.size(); ++a) col[static_cast<std::size_t>(beta) * alphas.size() + a] = s * mono[a];
    }
  }
}

}  // namespace vrsph
