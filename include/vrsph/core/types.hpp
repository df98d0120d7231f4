// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Basic scalar, index and vector types shared by every vrsph module.
//
// Positions are always stored as 3-vectors; in 1D and 2D the unused trailing
// coordinates are exactly zero. This keeps every stage (clouds, neighbour lists,
// stencils, I/O) dimension-agnostic at the API, so a runtime dimension needs no
// template dispatch outside the few hot loops that specialise on it internally.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace vrsph {

using Real = double;
/// Index type of particles and of CSR arrays. It is `int` so that a stencil can be
/// viewed as an Eigen sparse matrix without copying (Eigen's default StorageIndex).
using Index = int;
using Vec3 = Eigen::Vector3d;
using Field = Eigen::VectorXd;  ///< one value per particle

inline constexpr int max_dimension = 3;

}  // namespace vrsph
