// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// PointCloud: particle positions in 1D/2D/3D with a role tag per particle and
// optional outward normals. A plain value type; every stage takes it by const&.
#include <string_view>
#include <vrsph/cloud/domain.hpp>
#include <vrsph/core/types.hpp>

namespace vrsph {

/// Role of a particle in a discretisation.
///  Interior  – an unknown of a boundary value problem; operators are evaluated here.
///  Dirichlet – on the boundary, carries prescribed values.
///  Neumann   – on the boundary, carries a prescribed flux a du/dn (needs a normal).
///  Ghost     – outside the domain; supplies exact values so that no kernel is truncated
///              in operator (truncation-error) tests; never an unknown.
enum class Tag : std::uint8_t { Interior = 0, Dirichlet = 1, Neumann = 2, Ghost = 3 };

std::string_view to_string(Tag tag);
/// Accepts "interior", "dirichlet", "neumann", "ghost" (any case) or the digits 0..3.
/// Throws InputError otherwise.
Tag parse_tag(std::string_view text);

struct PointCloud {
  int dim = 2;                 ///< 1, 2 or 3
  std::vector<Vec3> positions; ///< unused coordinates are exactly 0
  std::vector<Tag> tags;       ///< one per particle
  std::vector<Vec3> normals;   ///< empty, or one outward unit normal per particle (0 where undefined)
  Real spacing = 0;            ///< nominal particle spacing dx; 0 = unknown (estimate_spacing() then)
  Domain domain;               ///< what the cloud discretises (Shape::None if unknown)

  Index size() const { return static_cast<Index>(positions.size()); }
  bool has_normals() const { return !normals.empty(); }
  Index count(Tag tag) const;
  /// Appends one particle (normal only if the cloud stores normals).
  void add(const Vec3& x, Tag tag, const Vec3& normal = Vec3::Zero());
};

/// Particles begin..end-1 of `cloud` (with their tags and normals; same dim, spacing, domain).
PointCloud slice(const PointCloud& cloud, Index begin, Index end);

/// Largest |coordinate| accepted: beyond it the squared distance of two particles
/// (up to 3 (2 max)^2) would overflow a double, and every search would find nothing.
inline constexpr Real max_coordinate = 1e150;

/// Checks the invariants that do not need a neighbour search: dimension in 1..3,
/// array sizes agree, every coordinate finite, |coordinates| <= max_coordinate, unused coordinates zero, normals
/// of Neumann particles (every dimension) unit vectors, at least one particle. Throws InputError naming
/// the first offending particle. (Duplicate points are reported by the neighbour
/// search, which sees every close pair anyway.)
void validate(const PointCloud& cloud);

/// The cloud's length unit for unit-free computations: the largest side of its bounding box
/// (1 when that is zero). Local systems written in it (VRSPH's moments, finite-difference
/// steps of expressions) are the same for a cloud in metres or in millimetres.
Real length_scale(const PointCloud& cloud);

/// Neumann normals must be unit vectors within this (validate); files and arrays are
/// scaled to unit length when read (normalise_normals), since only their direction means
/// anything and a flux row would otherwise be scaled by their length.
inline constexpr Real kUnitNormalTolerance = 1e-6;
/// Normals shorter than this are no direction: normalise_normals refuses them at Neumann particles.
inline constexpr Real kShortestNormal = 1e-3;
/// Scales every non-zero normal to unit length. Throws InputError naming a Neumann particle
/// whose normal is shorter than kShortestNormal (zero normals are left for validate to name).
void normalise_normals(PointCloud& cloud);

/// Nominal spacing: cloud.spacing if set, else (measure(domain)/N)^(1/d) if the
/// domain is known, else a robust local-density estimate: the median distance r_k to
/// the k-th neighbour (k = 12 in 2D, 32 in 3D) scaled by (omega_d/(k+1))^(1/d), and
/// the median gap between consecutive particles in 1D (within 2 % of dx on lattices,
/// perturbed or not). Throws GeometryError for fewer than 2 distinct particles.
Real estimate_spacing(const PointCloud& cloud);

}  // namespace vrsph
