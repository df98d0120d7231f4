// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/vrsph/moments.hpp>

namespace vrsph {

namespace {
std::size_t table_index(MomentConditions c) {
  return c == MomentConditions::Gradient ? 0 : c == MomentConditions::Laplace ? 1 : 2;
}
}  // namespace

const std::vector<std::array<int, 3>>& moment_exponents(MomentConditions c, int dim) {
  static const auto table = [] {
    std::array<std::array<std::vector<std::array<int, 3>>, 3>, 3> t;
    for (int d = 1; d <= 3; ++d)
      for (int deg = 0; deg <= 2; ++deg)
        for (int a0 = deg; a0 >= 0; --a0)
          for (int a1 = deg - a0; a1 >= 0; --a1) {
            const std::array<int, 3> a{a0, a1, deg - a0 - a1};
            if ((d < 2 && a[1]) || (d < 3 && a[2])) continue;
            t[1][static_cast<std::size_t>(d - 1)].push_back(a);                 // Laplace: |alpha| <= 2
            if (deg >= 1) t[0][static_cast<std::size_t>(d - 1)].push_back(a);   // Gradient: 1 <= |alpha| <= 2
            if (deg <= 1) t[2][static_cast<std::size_t>(d - 1)].push_back(a);   // WallLaplace: |alpha| <= 1
          }
    return t;
  }();
  check<ConfigError>(dim >= 1 && dim <= 3, "moment conditions: dimension must be 1, 2 or 3, got ", dim);
  return table[table_index(c)][static_cast<std::size_t>(dim - 1)];
}

int moment_rows(MomentConditions c, int dim) { return dim * static_cast<int>(moment_exponents(c, dim).size()); }

namespace {
// Position of x^g (1 <= |g| <= 3) in the monomial list of build_moment_system:
// x y z | xx xy xz yy yz zz | xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz.
int monomial_index(const std::array<int, 3>& g) {
  static constexpr std::array<std::array<int, 3>, 19> order{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 0}, {1, 1, 0},
                                                             {1, 0, 1}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2}, {3, 0, 0},
                                                             {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {1, 1, 1}, {1, 0, 2},
                                                             {0, 3, 0}, {0, 2, 1}, {0, 1, 2}, {0, 0, 3}}};
  for (std::size_t i = 0; i < order.size(); ++i)
    if (order[i] == g) return static_cast<int>(i);
  throw std::logic_error("moment row with an exponent of degree outside 1..3");
}

// Distinct gamma = alpha + e_beta with their multiplicity and target, in first-appearance order.
struct MergedRow {
  std::array<int, 3> gamma;
  Real weight;  // sqrt(multiplicity)
  Real target;  // 1 for gamma = 2 e_beta, else 0
  int monomial;  // monomial_index(gamma)
};
const std::vector<MergedRow>& merged_rows(MomentConditions c, int dim) {
  static const auto table = [] {
    std::array<std::array<std::vector<MergedRow>, 3>, 3> t;
    for (const auto cond : {MomentConditions::Gradient, MomentConditions::Laplace, MomentConditions::WallLaplace})
      for (int d = 1; d <= 3; ++d) {
        std::vector<std::pair<std::array<int, 3>, int>> rows;
        std::vector<Real> target;
        for (int beta = 0; beta < d; ++beta)
          for (const auto& al : moment_exponents(cond, d)) {
            std::array<int, 3> g = al;
            ++g[static_cast<std::size_t>(beta)];
            const bool one = al[0] + al[1] + al[2] == 1 && al[static_cast<std::size_t>(beta)] == 1;
            auto it = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == g; });
            if (it == rows.end()) {
              rows.emplace_back(g, 1);
              target.push_back(one ? 1.0 : 0.0);
            } else {
              ++it->second;  // identical row, identical target (both 0: only gamma = 2 e_beta has b = 1)
            }
          }
        auto& out = t[table_index(cond)][static_cast<std::size_t>(d - 1)];
        for (std::size_t r = 0; r < rows.size(); ++r) {
          const Real w = std::sqrt(static_cast<Real>(rows[r].second));
          out.push_back({rows[r].first, w, w * target[r], monomial_index(rows[r].first)});
        }
      }
    return t;
  }();
  return table[table_index(c)][static_cast<std::size_t>(dim - 1)];
}
}  // namespace


int moment_rows(MomentConditions c, int dim, MomentRows layout) {
  return layout == MomentRows::Full ? moment_rows(c, dim) : static_cast<int>(merged_rows(c, dim).size());
}

void build_moment_system(MomentConditions c, int dim, const Vec3* xji, const Real* half_y, int n, Real* A, Real* b,
                         MomentRows layout, MatrixOrder order) {
  // Entry (r, j) at A[r + j m] (column-major) or A[r n + j] (row-major).
  const std::size_t rows_total = static_cast<std::size_t>(moment_rows(c, dim, layout));
  const std::size_t row_step = order == MatrixOrder::ColumnMajor ? 1 : static_cast<std::size_t>(n);
  const std::size_t col_step = order == MatrixOrder::ColumnMajor ? rows_total : 1;
  if (layout == MomentRows::Merged) {
    const auto& rows = merged_rows(c, dim);
    const std::size_t m = rows.size();
    for (std::size_t r = 0; r < m; ++r) b[r] = rows[r].target;
    // Each row is weight * (Y/2) * x^gamma with 1 <= |gamma| <= 3: the monomials of degree
    // 1..3 are formed once per neighbour (straight-line code, 19 in 3D) and each row picks
    // one by its index in that list (the per-row products of powers were 8% of the volumes).
    std::array<int, 32> pick{};
    std::array<Real, 32> weight{};
    for (std::size_t r = 0; r < m; ++r) {
      pick[r] = rows[r].monomial;
      weight[r] = rows[r].weight;
    }
    Real mono[20];
    for (int j = 0; j < n; ++j) {
      const Real x = xji[j][0], y = xji[j][1], z = xji[j][2];
      // Degree 1, 2, 3 in a fixed order (see monomial_index).
      mono[0] = x; mono[1] = y; mono[2] = z;
      mono[3] = x * x; mono[4] = x * y; mono[5] = x * z; mono[6] = y * y; mono[7] = y * z; mono[8] = z * z;
      mono[9] = mono[3] * x; mono[10] = mono[3] * y; mono[11] = mono[3] * z; mono[12] = mono[6] * x;
      mono[13] = mono[4] * z; mono[14] = mono[8] * x; mono[15] = mono[6] * y; mono[16] = mono[6] * z;
      mono[17] = mono[8] * y; mono[18] = mono[8] * z;
      const Real hy = half_y[j];
      Real* col = A + static_cast<std::size_t>(j) * col_step;
      for (std::size_t r = 0; r < m; ++r) col[r * row_step] = weight[r] * hy * mono[pick[r]];
    }
    return;
  }
  const auto& alphas = moment_exponents(c, dim);
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
    Real* col = A + static_cast<std::size_t>(j) * col_step;
    for (int beta = 0; beta < dim; ++beta) {
      const Real s = half_y[j] * d[beta];
      for (std::size_t a = 0; a < alphas.size(); ++a)
        col[(static_cast<std::size_t>(beta) * alphas.size() + a) * row_step] = s * mono[a];
    }
  }
}

void moment_targets(MomentConditions c, int dim, MomentRows layout, const MomentTarget& t, Real* b) {
  check<ConfigError>(c != MomentConditions::Gradient, "moment targets apply to the Laplace conditions only");
  // Row (beta, alpha) of the literal system: Σ v (Y/2) x^(alpha + e_beta); its target is
  // first_beta / 2 for alpha = 0 (Σ w x_beta = first_beta) and second_beta for alpha = e_beta.
  const auto target = [&](const std::array<int, 3>& gamma) -> Real {
    const int degree = gamma[0] + gamma[1] + gamma[2];
    for (int k = 0; k < dim; ++k) {
      if (degree == 1 && gamma[static_cast<std::size_t>(k)] == 1) return 0.5 * t.first[k];
      if (degree == 2 && gamma[static_cast<std::size_t>(k)] == 2) return t.second[k];
    }
    return 0;
  };
  if (layout == MomentRows::Merged) {
    const auto& rows = merged_rows(c, dim);
    for (std::size_t r = 0; r < rows.size(); ++r) b[r] = rows[r].weight * target(rows[r].gamma);
    return;
  }
  const auto& alphas = moment_exponents(c, dim);
  for (int beta = 0; beta < dim; ++beta)
    for (std::size_t a = 0; a < alphas.size(); ++a) {
      std::array<int, 3> g = alphas[a];
      ++g[static_cast<std::size_t>(beta)];
      // Only (beta, alpha = 0) reaches gamma = e_beta and (beta, e_beta) reaches 2 e_beta.
      b[static_cast<std::size_t>(beta) * alphas.size() + a] = target(g);
    }
}

int first_moment_row(MomentConditions c, int dim, MomentRows layout, int k) {
  check<ConfigError>(c != MomentConditions::Gradient && k >= 0 && k < dim,
                     "first_moment_row: Laplace conditions and an axis below the dimension");
  if (layout == MomentRows::Full) return k * static_cast<int>(moment_exponents(c, dim).size());  // (beta = k, alpha = 0)
  const auto& rows = merged_rows(c, dim);
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (rows[r].gamma[0] + rows[r].gamma[1] + rows[r].gamma[2] == 1 && rows[r].gamma[static_cast<std::size_t>(k)] == 1)
      return static_cast<int>(r);
  throw std::logic_error("first_moment_row: no row x_k");
}

void nearest_first_scales(std::span<const Real> distances, std::vector<Real>& scale) {
  Real r_min = std::numeric_limits<Real>::infinity();
  for (const Real d : distances) r_min = std::min(r_min, d);
  scale.resize(distances.size());
  for (std::size_t j = 0; j < distances.size(); ++j) scale[j] = std::pow(r_min / distances[j], 2);
}

}  // namespace vrsph
