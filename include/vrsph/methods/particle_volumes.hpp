// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// One volume V_j per particle, for methods that weight neighbours by a volume ([IM] gpm)
// and for the Voronoi deviation d_N (analysis/regularity.hpp):
//   uniform  |Omega| / N ([IM] §5.4; needs the cloud's domain),
//   voronoi  |sigma_j|, the Voronoi cell clipped to the domain (then d_N = 0),
//   vrsph    VRSPH's Laplace-condition volumes v^(i)_j ([QW] §4) averaged over the rows i
//            that hold j — one global volume per particle from VRSPH's row-wise ones.
#include <string>
#include <vector>
#include <vrsph/methods/method.hpp>

namespace vrsph {

enum class ParticleVolumes { Uniform, Voronoi, Vrsph };
ParticleVolumes parse_particle_volumes(const std::string& name);
const char* particle_volumes_name(ParticleVolumes v);

/// One volume per particle of disc.cloud (vrsph uses disc's neighbours and kernel).
std::vector<Real> particle_volumes(const Discretisation& disc, ParticleVolumes kind);

}  // namespace vrsph
