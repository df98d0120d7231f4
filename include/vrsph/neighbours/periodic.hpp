// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Periodic clouds: the images of particles near periodic faces, and the shift of a pair
// across them. A cloud whose box is periodic along some axes (Domain::periodic) is
// searched with minimum-image distances (find_neighbours): each pair (i, j) stores the
// image of j that i sees, as a shift code, so x_j + shift - x_i is the pair's vector.
// Methods build their rows on the cloud extended by images (every method unchanged: its
// rows read ordinary positions) and the columns are folded back onto the originals.
#include <cstdint>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/neighbours/neighbour_list.hpp>

namespace vrsph {

/// Shift code of an image: s = (s_x + 1) + 3 (s_y + 1) + 9 (s_z + 1), each s_k in {-1, 0, 1}
/// periods; 13 is no shift.
inline constexpr std::uint8_t no_shift = 13;
/// The code of the shift by (s_x, s_y, s_z) periods.
constexpr std::uint8_t shift_code(int sx, int sy, int sz) {
  return static_cast<std::uint8_t>((sx + 1) + 3 * (sy + 1) + 9 * (sz + 1));
}
/// The periods s_k in {-1, 0, 1} along axis k (0, 1, 2) of the shift with this code.
constexpr int axis_shift(std::uint8_t code, int k) {
  int c = code;
  for (; k > 0; --k) c /= 3;
  return c % 3 - 1;
}
/// The displacement of an image with this code in this domain.
Vec3 periodic_shift(const Domain& domain, std::uint8_t code);

struct SearchParams;

struct PeriodicImages {
  /// The originals (first, in their order) and the images of those within `width` of a
  /// periodic face (each combination of the periodic axes), with the originals' tags and
  /// normals; its domain is the original's.
  PointCloud cloud;
  std::vector<Index> image_of;     ///< per particle of `cloud`: its original (originals: themselves)
  std::vector<std::uint8_t> shift; ///< per particle of `cloud`: its shift code (originals: no_shift)
  Index originals = 0;

  /// Values over the originals (rows) at every particle of `cloud`: each image takes its original's.
  Eigen::MatrixXd expand(const Eigen::MatrixXd& values) const;
  Field expand(const Field& values) const;
  /// The plain search of `cloud` with the originals' radii (`search.radius`, or `search.radii`
  /// over the originals) at their images; only the originals' rows are held to
  /// `search.min_neighbours` (an image's row is cut at the edge of the images).
  NeighbourList search(const SearchParams& search) const;
};

/// Checks a periodic cloud for a search of this radius: each periodic axis's period larger
/// than twice the radius (else a particle would meet two images of one neighbour), every
/// particle inside [lo, hi) along the periodic axes (InputError naming the first outside:
/// the library refuses rather than wraps; wrap them with Domain::wrap).
void check_periodic_cloud(const PointCloud& cloud, Real radius);
/// The cloud with the images of its particles within `width` (less than a period; ConfigError
/// otherwise) of a periodic face.
PeriodicImages periodic_images(const PointCloud& cloud, Real width);
/// The shift codes of x's images within `width` of the box (of a face it is near, along each
/// periodic axis of the first `dim`), in the order periodic_images lists them: no_shift first,
/// then loops over x, y, z, each taking the shifts 0, +1, -1 that apply.
std::vector<std::uint8_t> image_codes(const Domain& domain, int dim, const Vec3& x, Real width);
/// Distance from each particle to its k-th nearest other particle with minimum-image distances
/// along the box's periodic axes (kth_neighbour_distance otherwise): what a knn support radius
/// h_i = factor * dist_k reads on a periodic cloud, where the plain distance of a particle near a
/// face misses the neighbours across it. ConfigError when a particle's k-th neighbour lies half a
/// period away or more (it would count two images of one neighbour: too few particles across).
std::vector<Real> minimum_image_kth_neighbour_distance(const PointCloud& cloud, int k);
/// ConfigError unless `width` (how far rows read: the images' or a halo's width) is less than
/// every periodic axis's period among the first `dim`; `what` names that width in the message.
void check_image_width(const Domain& domain, int dim, Real width, const char* what);

}  // namespace vrsph
