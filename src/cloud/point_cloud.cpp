// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <string>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

std::string_view to_string(Tag tag) {
  switch (tag) {
    case Tag::Interior: return "interior";
    case Tag::Dirichlet: return "dirichlet";
    case Tag::Neumann: return "neumann";
    case Tag::Ghost: return "ghost";
  }
  return "?";
}

Tag parse_tag(std::string_view text) {
  std::string t(text);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (t == "interior" || t == "0") return Tag::Interior;
  if (t == "dirichlet" || t == "1") return Tag::Dirichlet;
  if (t == "neumann" || t == "2") return Tag::Neumann;
  if (t == "ghost" || t == "3") return Tag::Ghost;
  throw InputError("unknown particle tag '" + printable(text) +
                   "' (expected interior, dirichlet, neumann, ghost or 0..3)");
}

Index PointCloud::count(Tag tag) const {
  return static_cast<Index>(std::count(tags.begin(), tags.end(), tag));
}

void PointCloud::add(const Vec3& x, Tag tag, const Vec3& normal) {
  positions.push_back(x);
  tags.push_back(tag);
  if (has_normals()) normals.push_back(normal);
}

void validate(const PointCloud& cloud) {
  check<InputError>(cloud.dim >= 1 && cloud.dim <= 3, "point cloud dimension must be 1, 2 or 3, got ", cloud.dim);
  check<InputError>(!cloud.positions.empty(), "point cloud is empty");
  check<InputError>(cloud.tags.size() == cloud.positions.size(), "point cloud has ", cloud.positions.size(),
                    " positions but ", cloud.tags.size(), " tags");
  check<InputError>(cloud.normals.empty() || cloud.normals.size() == cloud.positions.size(), "point cloud has ",
                    cloud.positions.size(), " positions but ", cloud.normals.size(), " normals");
  check<InputError>(std::isfinite(cloud.spacing) && cloud.spacing >= 0,
                    "point cloud spacing must be finite and >= 0, got ", cloud.spacing);
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) {
      check<InputError>(std::isfinite(x[k]), "particle ", i, " has a non-finite coordinate ", "xyz"[k], " = ", x[k]);
      check<InputError>(std::abs(x[k]) <= max_coordinate, "particle ", i, " has coordinate ", "xyz"[k], " = ", x[k],
                        " beyond +-", max_coordinate, ": squared distances would overflow; rescale the cloud");
      check<InputError>(k < cloud.dim || x[k] == 0, "particle ", i, " has a non-zero coordinate ", "xyz"[k], " = ",
                        x[k], " in a ", cloud.dim, "D cloud (dimension mismatch)");
    }
    const auto tag = static_cast<unsigned>(cloud.tags[static_cast<std::size_t>(i)]);
    check<InputError>(tag <= 3u, "particle ", i, " has an invalid tag value ", tag);
    if (cloud.has_normals()) {
      const Vec3& n = cloud.normals[static_cast<std::size_t>(i)];
      check<InputError>(n.allFinite(), "particle ", i, " has a non-finite normal");
    }
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Neumann) {
      // Every dimension: a 1D Neumann end needs its direction (nx = -1 or +1) as much as a wall.
      const bool given = cloud.has_normals() && cloud.normals[static_cast<std::size_t>(i)] != Vec3::Zero();
      check<InputError>(given, "Neumann particle ", i, " at (", x[0], ", ", x[1], ", ", x[2], ") has no outward normal (give ",
                        cloud.dim == 1 ? "an nx column: -1 at the left end, +1 at the right" : "nx,ny[,nz] columns", ")");
      const Vec3& n = cloud.normals[static_cast<std::size_t>(i)];
      check<InputError>(std::abs(n.norm() - 1) <= kUnitNormalTolerance, "Neumann particle ", i, " at (", x[0], ", ", x[1],
                        ", ", x[2], ") has a normal (", n[0], ", ", n[1], ", ", n[2], ") of length ", n.norm(),
                        "; normals must be unit vectors (normalise_normals scales them)");
    }
  }
}

Real length_scale(const PointCloud& cloud) {
  if (cloud.positions.empty()) return 1;
  Vec3 lo = cloud.positions.front(), hi = lo;
  for (const Vec3& x : cloud.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Real side = (hi - lo).maxCoeff();
  return side > 0 && std::isfinite(side) ? side : 1;
}

void normalise_normals(PointCloud& cloud) {
  for (std::size_t i = 0; i < cloud.normals.size(); ++i) {
    Vec3& n = cloud.normals[i];
    const Real len = n.norm();
    if (len == 0 || !std::isfinite(len)) continue;  // none given here (interior), or validate names it
    check<InputError>(len >= kShortestNormal || i >= cloud.tags.size() || cloud.tags[i] != Tag::Neumann,
                      "Neumann particle ", i, " has a normal (", n[0], ", ", n[1], ", ", n[2], ") of length ", len,
                      ", too short to give a direction (a normal is a unit vector; ", kShortestNormal, " is the shortest "
                      "length scaled to one)");
    // (Unit to round-off already: kept bit for bit, so a file read back equals the one written.)
    if (len >= kShortestNormal && std::abs(len - 1) > 1e-12) n /= len;
  }
}

namespace {
Real median(std::vector<Real> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Spacing of a cloud without a known domain, from its local density: the median over
// particles of the distance r_k to the k-th neighbour, with k + 1 particles in a ball
// of volume omega_d r_k^d. k = 12 (2D) and 32 (3D) put r_k beyond the lattice shells
// that bias smaller k; measured: 0.98 dx on a square lattice, 0.99 dx on a lattice
// perturbed by U(-dx/2, dx/2), where the mean nearest-neighbour distance gives 0.66 dx.
// 1D: the median gap between consecutive particles. Clouds too small for k use the mean
// nearest-neighbour distance. 0 means every particle has a duplicate.
Real robust_spacing(const PointCloud& cloud) {
  if (cloud.dim == 1) {
    std::vector<Real> x;
    for (const Vec3& p : cloud.positions) x.push_back(p[0]);
    std::sort(x.begin(), x.end());
    std::vector<Real> gaps;
    for (std::size_t i = 1; i < x.size(); ++i)
      if (x[i] > x[i - 1]) gaps.push_back(x[i] - x[i - 1]);
    return gaps.empty() ? 0 : median(gaps);
  }
  const int k = cloud.dim == 2 ? 12 : 32;
  if (cloud.size() <= 4 * k) return mean_nearest_neighbour_distance(cloud);
  const Real ball = cloud.dim == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  return median(kth_neighbour_distance(cloud, k)) * std::pow(ball / (k + 1), 1.0 / cloud.dim);
}
}  // namespace

Real estimate_spacing(const PointCloud& cloud) {
  if (cloud.spacing > 0) return cloud.spacing;
  check<GeometryError>(cloud.size() >= 2, "the cloud has only ", cloud.size(),
                       " particle: no spacing, no neighbours, no operator (at least 2 distinct particles are needed)");
  const Real measure = cloud.domain.measure();
  if (measure > 0) {
    // Count only the particles that discretise the domain (ghosts lie outside it).
    const Index inside = cloud.size() - cloud.count(Tag::Ghost);
    return std::pow(measure / static_cast<Real>(std::max<Index>(inside, 1)), 1.0 / cloud.dim);
  }
  const Real spacing = robust_spacing(cloud);
  if (!(spacing > 0)) {
    const Vec3& x = cloud.positions.front();
    const bool all_same = std::all_of(cloud.positions.begin(), cloud.positions.end(), [&](const Vec3& y) { return y == x; });
    check<GeometryError>(!all_same, "all ", cloud.size(), " particles are at the same position (", x[0], ", ", x[1], ", ",
                         x[2], "): the cloud has no extent");
    throw InputError(detail::concat("every particle has a duplicate at distance 0 (each position occurs more than once): "
                                    "remove the duplicate particles"));
  }
  return spacing;
}

PointCloud slice(const PointCloud& cloud, Index begin, Index end) {
  check<InputError>(0 <= begin && begin <= end && end <= cloud.size(), "slice ", begin, "..", end, " of a cloud of ",
                    cloud.size(), " particles");
  PointCloud part;
  part.dim = cloud.dim;
  part.spacing = cloud.spacing;
  part.domain = cloud.domain;
  part.positions.assign(cloud.positions.begin() + begin, cloud.positions.begin() + end);
  part.tags.assign(cloud.tags.begin() + begin, cloud.tags.begin() + end);
  if (cloud.has_normals()) part.normals.assign(cloud.normals.begin() + begin, cloud.normals.begin() + end);
  return part;
}

}  // namespace vrsph
