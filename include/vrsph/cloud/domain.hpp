// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The geometric domain a cloud discretises: an axis-aligned box or a ball.
// Used to tell near-boundary particles from interior ones, to clip Voronoi
// cells (covering radius) and to give boundary particles their outward normals.
#include <vrsph/core/types.hpp>

namespace vrsph {

struct Domain {
  enum class Shape { None, Box, Ball };
  Shape shape = Shape::None;
  int dim = 0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< Box corners (unused coordinates 0)
  Vec3 centre = Vec3::Zero();                 ///< Ball centre
  Real radius = 0;                            ///< Ball radius

  static Domain box(int dim, const Vec3& lo, const Vec3& hi);
  /// The unit box [0,1]^d or the symmetric box [-a,a]^d.
  static Domain unit_box(int dim);
  static Domain symmetric_box(int dim, Real half_width);
  static Domain ball(int dim, const Vec3& centre, Real radius);

  /// Signed distance to the boundary: positive inside, negative outside.
  /// Shape::None returns +infinity (nothing is near a boundary).
  Real signed_distance(const Vec3& x) const;
  /// d-dimensional measure (length, area, volume); 0 for Shape::None.
  Real measure() const;
  /// Outward unit normal of the nearest boundary piece (box: the face with the
  /// smallest distance; at edges/corners the normalised sum of the faces within tol).
  Vec3 outward_normal(const Vec3& x, Real tol = 0) const;
};

}  // namespace vrsph
