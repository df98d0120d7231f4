// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The geometric domain a cloud discretises: an axis-aligned box or a ball.
// Used to tell near-boundary particles from interior ones, to clip Voronoi
// cells (covering radius) and to give boundary particles their outward normals.
// A box may be periodic along any subset of its axes (period hi - lo): those faces are
// no boundary, and a particle near one sees its neighbours across the opposite face.
#include <array>
#include <string>
#include <vrsph/core/types.hpp>

namespace vrsph {

struct Domain {
  enum class Shape { None, Box, Ball };
  Shape shape = Shape::None;
  int dim = 0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< Box corners (unused coordinates 0)
  Vec3 centre = Vec3::Zero();                 ///< Ball centre
  Real radius = 0;                            ///< Ball radius
  std::array<bool, 3> periodic{false, false, false};  ///< Box: periodic axes (period hi - lo)

  static Domain box(int dim, const Vec3& lo, const Vec3& hi);
  /// The unit box [0,1]^d or the symmetric box [-a,a]^d.
  static Domain unit_box(int dim);
  static Domain symmetric_box(int dim, Real half_width);
  static Domain ball(int dim, const Vec3& centre, Real radius);
  /// The box [lo, hi) periodic along `axes` ("x,y", "all"; set_periodic): corners finite and
  /// within +-max_coordinate, hi > lo, a finite volume. InputError otherwise (ConfigError for an
  /// unknown axis). Particles must then lie in [lo, hi) along the periodic axes
  /// (check_periodic_cloud): a periodic box is never inferred from the particles, whose last
  /// layer sits a spacing short of the far face.
  static Domain periodic_box(int dim, const Vec3& lo, const Vec3& hi, const std::string& axes);

  /// Signed distance to the boundary: positive inside, negative outside.
  /// Shape::None returns +infinity (nothing is near a boundary); a periodic axis has no
  /// boundary (a fully periodic box: +infinity).
  Real signed_distance(const Vec3& x) const;
  /// d-dimensional measure (length, area, volume); 0 for Shape::None.
  Real measure() const;
  /// Whether any axis is periodic, and whether every axis of the dimension is.
  bool any_periodic() const;
  bool fully_periodic() const;
  Real period(int axis) const { return hi[axis] - lo[axis]; }
  /// The shortest period among the periodic axes of the dimension (+infinity without one).
  Real shortest_period() const;
  /// x moved by whole periods into [lo, hi) along the periodic axes.
  Vec3 wrap(const Vec3& x) const;
  /// The box periodic along these axes ("x,y", "all" or "" for none); throws ConfigError
  /// for an unknown axis, InputError for a shape that is not a box.
  void set_periodic(const std::string& axes);
  /// "x,y" for the periodic axes ("" for none).
  std::string periodic_axes() const;

  /// Outward unit normal of the nearest boundary piece (box: the face with the
  /// smallest distance; at edges/corners the normalised sum of the faces within tol).
  Vec3 outward_normal(const Vec3& x, Real tol = 0) const;
};

}  // namespace vrsph
