// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The papers' boundary value problems for the studies (analysis/bvp_study.hpp), handed in as
// a catalogue so that the study itself knows no paper:
//   aar-static      [AAR] §5 elastic static test: -u'' = e^x on [0,1], u(0) = 0, u'(1) = 0
//                   (traction-free end: a Neumann particle), exact u = -e^x + e x + 1;
//   spe-dirichlet,  [SPE] §5 Laplace problems on the unit square (spe_problems.hpp), the
//   spe-mixed       support 2 f dx for the h-factor f.
// qw-ex5, [QW] Example 5, is the library's built-in default problem.
#include <vrsph/analysis/bvp_study.hpp>

namespace vrsph {

StudyProblemCatalogue published_problems();

}  // namespace vrsph
