// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The exponents of the monomials x^a y^b z^c of degree 1 ... max_degree in `dim` variables, degree
// by degree and, within a degree, by descending power of x then y: the one ordering of the moment
// systems that are built per row (VRSPH's compact rows, gradient rows exact on cubics). constexpr:
// the rows exact on polynomials take their exponents as compile-time constants.
#include <array>
#include <vector>

namespace vrsph {

constexpr std::vector<std::array<int, 3>> monomial_exponents(int dim, int max_degree) {
  std::vector<std::array<int, 3>> out;
  for (int deg = 1; deg <= max_degree; ++deg)
    for (int a0 = deg; a0 >= 0; --a0)
      for (int a1 = deg - a0; a1 >= 0; --a1) {
        const std::array<int, 3> a{a0, a1, deg - a0 - a1};
        if ((dim < 2 && a[1]) || (dim < 3 && a[2])) continue;
        out.push_back(a);
      }
  return out;
}

}  // namespace vrsph
