// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Free-surface detection: which particles of a fluid cloud lie on its free surface, and the
// outward surface normal there. Two criteria, both on the kernel sums of a support radius
// h = h_factor dx (Wendland C2 by default), normalised by the same sums over a full lattice
// of spacing dx so that an interior particle of a lattice reads exactly 1:
//
//  * NumberDensity (the MPS/ISPH practice, Koshizuka & Oka 1996): surface iff
//    n_i / n_0 < density_threshold, with n_i = sum_j W(r_ij) (self included). Cheap, but
//    it flags a band (every particle whose support the surface cuts enough) and, on disordered
//    clouds, interior particles next to a void.
//  * Eigenvalue (Doring 2005; Marrone et al., Comput. Phys. Commun. 181 (2010) 1168–1177):
//    lambda_i, the smallest eigenvalue of M_i = sum_j V (-W'(r)/r) x_ij x_ij^T (the inverse of
//    the kernel-gradient renormalisation matrix; V = dx^d). lambda_i < surface_eigenvalue:
//    surface (isolated and thin parts); lambda_i > interior_eigenvalue: interior; in between
//    the scan decides: i is on the surface iff no neighbour lies in the region
//    {|x - x_i| < sqrt(2) s, angle(x - x_i, n_i) < 45 deg} U {|x - (x_i + s n_i)| < s},
//    s = h / 2, n_i the normal below. The scan removes the false positives of the eigenvalue
//    alone next to corners and inside disordered clouds. A neighbour that is surface without
//    a scan (lambda_j < surface_eigenvalue: a droplet, a filament's tip, a sharp crest) does
//    not cover i: spray 1.5-2.5 dx above the water hid the particles under it from the air
//    (interior rows, whose pressure then spiked; docs/free_surface.md). Marrone et al. count
//    every neighbour (scan_every_neighbour).
//    With walls (only_interior), films: a fluid particle whose support is open (lambda_i
//    below interior_eigenvalue, walls counted) and whose fluid neighbours alone are thin (the
//    smallest eigenvalue of M_i over them below film_eigenvalue, 0.1) is surface, its normal
//    the eigenvector across them, on the side n_i points to. A jet one particle thick running
//    up a wall had lambda_i = 0.31 with the walls; its n_i was turned along the jet by a
//    neighbour 0.55 dx above, the particle below then lay in the scan's cap, and its interior
//    pressure row, between the walls and p = 0, swung until the jet was flung off (dam break;
//    docs/free_surface.md). A water particle in a corner of walls has lambda_i near 1.
//
// Normal: n_i = -M_i^{-1} sum_j V grad_i W_ij, normalised (the renormalised gradient of the
// Shepard sum points into the fluid); without renormalisation where M_i is singular, 0 where
// the gradient vanishes (a lone particle). Normals are given at every particle whose lambda
// is below interior_eigenvalue (the surface and the band under it), 0 elsewhere.
//
// Walls: with only_interior, particles tagged Dirichlet/Neumann/Ghost count as neighbours
// (a fluid particle next to a wall has a full support) but are never flagged, and in the scan
// they cover a particle only inside its cone (the cap of a particle at the foot of a water
// column's free face reaches down to the floor beside it). Periodic boxes
// are searched across their periodic faces.
#include <cstdint>
#include <string_view>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/kernels/kernel.hpp>

namespace vrsph {

enum class SurfaceCriterion { Eigenvalue, NumberDensity };
std::string_view surface_criterion_name(SurfaceCriterion c);
/// "eigenvalue" or "number-density"; ConfigError otherwise.
SurfaceCriterion parse_surface_criterion(std::string_view name);

struct FreeSurfaceOptions {
  SurfaceCriterion criterion = SurfaceCriterion::Eigenvalue;
  KernelType kernel = KernelType::WendlandC2;
  Real h_factor = 2.5;             ///< support radius / spacing
  Real spacing = 0;                ///< dx; 0 = estimate_spacing(cloud)
  Real density_threshold = 0.97;   ///< NumberDensity: surface iff n/n_0 below this (MPS: 0.97)
  Real surface_eigenvalue = 0.2;   ///< Eigenvalue: surface without a scan below this
  Real interior_eigenvalue = 0.75; ///< Eigenvalue: interior without a scan above this
  bool scan = true;                ///< Eigenvalue: run the scan in between (false: surface iff lambda <= interior_eigenvalue)
  bool only_interior = false;      ///< classify Interior particles only; the others are walls/ghosts
  /// Eigenvalue: every neighbour covers in the scan, droplets included (Marrone et al. 2010
  /// as published); false: neighbours with lambda_j < surface_eigenvalue do not.
  bool scan_every_neighbour = false;
  /// Eigenvalue with only_interior: a fluid particle with lambda_i below interior_eigenvalue
  /// whose fluid neighbours alone (walls left out) give a smallest eigenvalue below this (of
  /// lambda_0) is surface, its normal across them: a film or jet one particle thick along a
  /// wall, whose support the walls' layers fill on one side. 0: off (the scan alone decides).
  Real film_eigenvalue = 0.1;
};

struct FreeSurface {
  std::vector<std::uint8_t> surface;  ///< 1 on the free surface
  std::vector<Vec3> normals;          ///< outward unit normal (see above), 0 where none
  std::vector<Real> density_ratio;    ///< n_i / n_0
  std::vector<Real> eigenvalue;       ///< lambda_i / lambda_0
  std::vector<std::uint8_t> scanned;  ///< Eigenvalue: 1 where the scan decided
  Index count = 0;                    ///< surface particles
  Real spacing = 0, radius = 0;       ///< dx and the support radius used
};

/// Throws InputError for an invalid cloud or duplicate particles, ConfigError for thresholds
/// outside (0, 1), surface_eigenvalue > interior_eigenvalue, a non-positive h_factor/spacing.
FreeSurface detect_free_surface(const PointCloud& cloud, const FreeSurfaceOptions& options = {});

}  // namespace vrsph
