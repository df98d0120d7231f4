// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The FPM variants of [AAR] (METHODS §3.6), 1D only:
//   mfpm   modified FPM (33)–(37): per particle the 2x2 system in (DB_i, D2B_i) obtained by
//          projecting the second-order Taylor expansion of B_j - B_i on W_i and DW_i.
//          Claimed: D2 O(h^2) inside, O(h) at the boundary (38).
//   fpm2o  second-order FPM (39)–(44): the same 2x2 system with W_i replaced by the
//          corrected kernel K_i = (a s^3 + b s + c) W_i, s = (x - x_i)/h, whose 0th, 1st and
//          3rd moments are (1, 0, 0) (3x3 system per particle). Claimed: O(h^2) everywhere.
// First derivative = first component of the 2x2 solve (the method's own Neumann row).
// Not extended to 2D/3D: the 2x2 projection on (W, DW) has no square d-dimensional
// counterpart (1 + d test functions against d + d(d+1)/2 unknowns); the second-order fpm
// is the multi-dimensional analogue.
// div(a grad u) = a_i D2 + (Da)_i D (METHODS §3.0).
#include <vrsph/methods/method.hpp>

namespace vrsph {

MethodInfo mfpm_info();
MethodInfo fpm2o_info();
std::unique_ptr<Method> make_mfpm(const MethodOptions& options);
std::unique_ptr<Method> make_fpm2o(const MethodOptions& options);

}  // namespace vrsph
