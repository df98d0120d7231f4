// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The coefficient of a particle pair in flux-form (two-point) operators, sum_j w_ij
// c(a_i, a_j) (u_j - u_i): the printed schemes ([QW] Morris form, [SPE] (52)/(69)) use
// c = a_i + a_j; across a jump of a (layered or channelised media) that lets a
// high-permeability particle leak into a low one at the rate of the high one. The
// harmonic form c = 4 a_i a_j / (a_i + a_j) (twice the harmonic mean, as in the
// finite-volume TPFA and in SPH heat conduction across materials) gives the series
// resistance instead. Both equal 2 a(midpoint) + O(|x_i - x_j|²) for smooth a, so the
// consistency order is the same.
#include <string>
#include <utility>
#include <vrsph/core/types.hpp>
#include <vrsph/methods/options.hpp>

namespace vrsph {

enum class PairMean { Arithmetic, Harmonic };

/// The method option `mean` (arithmetic by default: the published forms).
inline PairMean read_pair_mean(const MethodOptions& o) {
  return o.get_choice("mean", "arithmetic", {"arithmetic", "harmonic"}) == "harmonic" ? PairMean::Harmonic
                                                                                       : PairMean::Arithmetic;
}

/// Twice the pair mean of a_i, a_j > 0 (the a_i + a_j of the printed schemes).
inline Real pair_sum(PairMean mean, Real ai, Real aj) {
  return mean == PairMean::Arithmetic ? ai + aj : 4 * ai * aj / (ai + aj);
}

/// The option's entry for MethodInfo::options.
inline std::pair<std::string, std::string> pair_mean_option() {
  return {"mean", "pair coefficient of div(a grad): arithmetic (a_i + a_j, the published form; default) | harmonic "
                  "(4 a_i a_j / (a_i + a_j): series resistance across jumps of a, as TPFA)"};
}

}  // namespace vrsph
