#pragma once
// Internal: the negative-transmissibility and [SPE] ξ summary of the interior rows, shared
// by the serial solve and each rank's rows of the distributed one.
#include <algorithm>
#include <cmath>
#include <vrsph/problem/boundary_value_problem.hpp>

namespace vrsph::detail {

// Negative off-diagonal weights of the interior rows and the [SPE] ξ diagnostic.
inline void summarise_transmissibilities(const Stencil& L, const std::vector<char>& interior, BvpSolution& s) {
  for (Index i = 0; i < L.rows(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (!interior[si]) continue;
    Index neg = 0;
    const Real scale = std::abs(L.values[0][static_cast<std::size_t>(L.diag[si])]);
    for (Index k = L.row_begin(i); k < L.row_end(i); ++k)
      neg += L.col[static_cast<std::size_t>(k)] != i && L.values[0][static_cast<std::size_t>(k)] < -1e-12 * scale;
    s.negative_transmissibilities += neg;
    if (neg > 0 && s.negative_rows.size() < 10) s.negative_rows.push_back(i);
    if (!L.xi.empty()) s.xi_max = std::isnan(s.xi_max) ? L.xi[si] : std::max(s.xi_max, L.xi[si]);
  }
}

}  // namespace vrsph::detail
