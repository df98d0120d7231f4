// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Boundary conditions by face of a box cloud: the faces x0, x1, y0, y1, z0, z1 (index
// 2 axis + side) of the cloud's Domain::Shape::Box.
#include <array>
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

/// Face names x0, x1, y0, y1, z0, z1 (or "all") -> on[2 axis + side]; ConfigError for an
/// unknown name or a face beyond the dimension.
std::array<bool, 6> parse_box_faces(const std::vector<std::string>& faces, int dim);

/// Retags as Neumann the boundary particles (Dirichlet-tagged) whose every face is one of
/// the faces with on[2 axis + side]; edges and corners shared with another face stay
/// Dirichlet. Their outward normal is the normalised sum of their faces' normals (a ball
/// has one face: on[0]). Returns how many were retagged; dx sets the on-face tolerance.
Index retag_neumann_faces(PointCloud& cloud, const std::array<bool, 6>& on, Real dx);

}  // namespace vrsph
