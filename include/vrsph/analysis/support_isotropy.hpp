// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Whether a particle's support still spans every dimension: the ratio of the smallest to the
// largest eigenvalue of its neighbours' second moments about it,
//   M_i = Σ_{r_ij < h_i} (1 - r_ij / h_i)² d_ij d_ijᵀ,  d_ij = x_j - x_i (the image i sees),
// 1 inside a lattice or any neighbourhood symmetric under the axes' exchange, about 0.4-0.5 at a
// lattice's faces and corners (the moments are about x_i, so a half support is not 0: the row along
// the face counts along it only), and -> 0 as the neighbours close onto a line (2D) or a plane
// (3D) through x_i. Flows stretch particles into such sheets near the
// saddle points of a vortex array without shifting; a support radius fixed in units of the
// initial spacing then no longer reaches across them and every row exact on linear functions
// loses its derivative across the sheet (docs/flow.md). The spacing of the nearest neighbour
// does not see this: the neighbours along the sheet stay close.
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>

namespace vrsph {

/// Per particle, λ_min(M_i) / λ_max(M_i) in [0, 1]; 0 for a particle with no neighbour inside its
/// radius. The list may hold pairs beyond each row's radius (a Verlet list): those are left out.
/// InputError when the list does not belong to the cloud (particle count, missing distances).
Field support_isotropy(const PointCloud& cloud, const NeighbourList& neighbours);

}  // namespace vrsph
