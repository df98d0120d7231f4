// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Voronoi cells clipped to the cloud's domain ([IM] sigma_i, METHODS §3.8.4): their
// measures |sigma_i| (length, area, volume) for the Voronoi deviation d_N and for
// Voronoi particle volumes (gpm volume=voronoi).
//
// The Delaunay neighbours of each particle (CGAL) give the bisector half-spaces of its
// cell; the cell is the domain box (or the disk's bounding box) cut by those half-spaces,
// done here by convex clipping: a polygon in 2D, a polyhedron kept as a list of faces in
// 3D. On a disk the area of polygon ∩ disk is exact (circular segments). Every particle,
// ghosts included, owns a cell, so the measures sum to |domain| up to round-off; cells of
// particles outside the domain may be empty (measure 0).
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

/// |sigma_i| for every particle. Box domains in 1D, 2D and 3D and disks in 2D; a 3D ball or
/// a cloud without a domain -> InputError; coincident particles -> GeometryError naming them.
/// A box periodic along some axes: the cells of the periodic tessellation (no clipping at its
/// periodic faces) when the cloud is `whole` and every particle lies inside the box; ConfigError
/// when a cell reaches half a period (too few particles across the box). A cloud that carries its
/// images explicitly (particles outside the box along a periodic axis, as periodic_stencil's
/// extended clouds) or that is a part (`whole` false: a rank's particles and halo) gets the cells
/// of its own points, the box widened along the periodic axes to hold them: exact wherever every
/// particle within twice a cell's reach is there, as a halo of two supports provides.
std::vector<Real> voronoi_cell_measures(const PointCloud& cloud, bool whole = true);

namespace detail {
/// The Delaunay neighbours of every particle (2D/3D, CGAL); throws GeometryError on
/// coincident particles. Defined in cloud/delaunay_neighbours.cpp.
std::vector<std::vector<Index>> delaunay_neighbours(const PointCloud& cloud);
}  // namespace detail

}  // namespace vrsph
