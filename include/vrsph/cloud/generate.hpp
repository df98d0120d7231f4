// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Seeded, reproducible point-cloud generators (METHODS.md §5 layouts).
// Every generator sets cloud.spacing (nominal dx) and cloud.domain, and stores an
// outward normal for boundary particles (zero elsewhere).
#include <cstdint>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

/// Part of a generated cloud: the particles numbered begin..end-1 of the whole cloud (one
/// rank's share of a distributed run, generated without the rest); end < 0: all of it.
struct ParticleRange {
  Index begin = 0, end = -1;
};

/// Layout A: vertices of a box lattice with n intervals per direction, dx = side/n;
/// particles on the faces are Dirichlet (with outward normals), the rest Interior.
/// ghost_layers > 0 continues the lattice that many layers outside (tag Ghost).
PointCloud vertex_lattice(const Domain& box, int n, int ghost_layers = 0, const ParticleRange& range = {});

/// Layout B: n^d cell centres, dx = side/n. With boundary_particles, also particles at
/// the boundary face centres, edges and corners (the lattice {lo, centres..., hi}^d),
/// tagged Dirichlet. ghost_layers > 0 continues the cell-centred lattice outside.
PointCloud cell_centred_lattice(const Domain& box, int n, bool boundary_particles, int ghost_layers = 0,
                                const ParticleRange& range = {});

/// Number of lattice layers needed outside the domain so that no kernel of support h
/// is truncated for particles inside: ceil((h + dx)/dx) (METHODS §4, width >= h + dx).
int ghost_layers_for(Real support_radius, Real dx);

struct PerturbOptions {
  Real delta = 0.5;                 ///< displacement U(-delta*dx, delta*dx) per coordinate ([QW]: 0.5)
  std::uint64_t seed = 1;
  bool boundary_tangential = false; ///< also move boundary particles along their face (not corners/edges)
  /// Box domains: interior particles closer than regular_layer * dx to a face keep their
  /// coordinate normal to that face (they move only tangentially). 0 = off. A regular
  /// first layer keeps VRSPH's Laplacian moment conditions feasible next to the boundary.
  Real regular_layer = 0;
  /// Number of the cloud's first particle in the whole cloud (a part made with
  /// ParticleRange): the random steps follow the whole cloud's numbering.
  Index first_index = 0;
  /// Whether the cloud has boundary particles (then interior steps stay inside the domain):
  /// -1 from the cloud itself; 0 or 1 given, for a part of a cloud (the whole cloud's answer:
  /// a part may hold none of the whole cloud's boundary particles).
  int bounded = -1;
};
/// Perturbs Interior and Ghost particles (and, optionally, boundary particles
/// tangentially). Random numbers are a counter-based hash of (seed, particle,
/// coordinate), so results do not depend on thread count or particle order.
/// Clouds with boundary particles keep interior particles inside the domain (a
/// displacement that would leave it is halved until it does not); clouds without
/// boundary particles are re-tagged afterwards (inside: Interior, outside: Ghost).
void perturb(PointCloud& cloud, const PerturbOptions& options);

/// Scattered particles in a disk (2D), ball (3D) or interval (1D) of the given radius
/// centred at the origin: interior particles on the lattice of spacing dx = 2R/n at
/// least dx/2 inside, boundary particles (Dirichlet, radial normals) evenly on the
/// surface at spacing ~dx (Fibonacci sphere in 3D). Numbering: the interior points row by
/// row (x outermost), then the surface ones; `range` makes only those particles.
PointCloud ball_cloud(int dim, Real radius, int n, const ParticleRange& range = {});
/// Particles of ball_cloud(dim, radius, n), counted without making them.
Index ball_cloud_size(int dim, Real radius, int n);

/// Centroids of a triangulation (2D) / tetrahedralisation (3D) of the box with maximum
/// edge length below dx ([QW] Example 3; METHODS P12 substitute for the MATLAB mesh):
/// CGAL Delaunay of a node lattice of spacing s = dx/1.85 (2D) or dx/2.3 (3D), nodes
/// jittered by U(-0.15 s, 0.15 s) (face nodes only tangentially, so the hull is the box).
/// The mesh covers the box enlarged by ghost_width; centroids outside the box are
/// Ghost. If boundary_particles, the mesh nodes on the box faces (ghost_width must be
/// 0) become Dirichlet particles. `max_edge` receives the longest mesh edge.
PointCloud mesh_centroids(const Domain& box, Real dx, std::uint64_t seed, Real ghost_width, bool boundary_particles,
                          Real* max_edge = nullptr);

/// Part `part` of `parts` of the mesh_centroids cloud, made without the rest: the particles
/// of a range of node layers along the last axis (see mesh_centroids.cpp), so that the
/// parts in order are the whole cloud's numbering (which is layer by layer: the centroids
/// of the simplices whose lowest-numbered node lies in the layer, then the layer's boundary
/// nodes). The spacing needs every part's `inside` count: it is left 0 here.
struct MeshCentroidsPart {
  PointCloud cloud;
  Real max_edge = 0;  ///< longest edge of this part's simplices
  Index inside = 0;   ///< particles not tagged Ghost
};
MeshCentroidsPart mesh_centroids_part(const Domain& box, Real dx, std::uint64_t seed, Real ghost_width,
                                      bool boundary_particles, int part, int parts);

}  // namespace vrsph
