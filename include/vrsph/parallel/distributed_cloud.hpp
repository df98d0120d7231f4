// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// DistributedCloud: a point cloud spread over MPI ranks.
//
// Numbering. Every particle has a *global id*: its place in the concatenation of the input
// chunks in rank order (rank 0's chunk first), i.e. its index in the serial cloud when the
// chunks are consecutive slices of it. Particles are re-partitioned along a Morton
// (Z-order) space-filling curve: rank r *owns* a contiguous range of the curve, about N/P
// particles, and a halo of every particle of other ranks within `halo_width` of its own.
//
// Local order. `local` holds the owned and halo particles sorted by global id. A method
// that builds row i from the particles within h of particle i, in index order, therefore
// sees exactly the neighbours, in exactly the order, of the serial run: the stencil rows
// of owned particles are the serial rows, bit for bit, whatever the number of ranks.
//
// Exchanges go through PETSc star forests (PetscSF): chunk -> owner (migration) and
// owner -> halo copies (ghost update), both ways.
#include <memory>
#include <span>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph {

namespace detail {
struct CloudExchange;  // the PetscSF graphs (distributed_cloud.cpp)
}

/// What the partition moved, per rank (bytes are payload: positions, tags, normals, ids).
struct DistributionStats {
  Index owned = 0, halo = 0;
  long long migration_bytes = 0;  ///< sent by this rank to re-partition
  long long halo_bytes = 0;       ///< sent by this rank to fill the other ranks' halos
  int halo_messages = 0;          ///< ranks this rank sends halo particles to
  double seconds = 0;
};

struct DistributedCloud {
  Communicator comm;
  PointCloud local;               ///< owned + halo, sorted by global id
  std::vector<Index> global_id;   ///< per local particle
  std::vector<char> owned;        ///< per local particle: 1 if this rank owns it
  Index owned_count = 0;
  Index global_size = 0;
  Real halo_width = 0;
  DistributionStats stats;
  std::shared_ptr<detail::CloudExchange> exchange;

  Index local_size() const { return local.size(); }
};

/// Partitions the union of every rank's `chunk` (collective). Each rank passes its part of
/// the cloud (any split, an empty chunk included); all chunks must agree on dim, domain
/// and spacing, and normals (present on every rank or on none). Throws, on every rank:
/// InputError (chunks disagree, non-finite coordinates: validate()), ConfigError (more
/// ranks than particles; a halo width that is not positive and finite).
DistributedCloud distribute(const PointCloud& chunk, Real halo_width, const Communicator& comm);

/// estimate_spacing (point_cloud.hpp) of the union of every rank's chunk, the same value on
/// every rank (collective): the chunks' spacing, else (|domain| / particles inside)^(1/d),
/// else the serial statistic (median k-th neighbour distance, 1D: median gap; small clouds:
/// mean nearest-neighbour distance) of the same per-particle distances, each computed by
/// its owner over a halo widened until no particle beyond it could change the distance.
/// Equal to the serial value (the mean to round-off). Throws as estimate_spacing does.
Real estimate_spacing_over_ranks(const PointCloud& chunk, const Communicator& comm);

/// Values of the input chunk (one per chunk particle, chunk order) at the local particles
/// (owned and halo, local order). Collective.
Field chunk_to_local(const DistributedCloud& dc, const Field& chunk_values);
Eigen::MatrixXd chunk_to_local(const DistributedCloud& dc, const Eigen::MatrixXd& chunk_values);
/// The owned particles' values back in the input chunk's order. Collective.
Field local_to_chunk(const DistributedCloud& dc, const Field& local_values);
/// Halo entries overwritten with their owners' values (owned entries unchanged). Collective.
void update_halo(const DistributedCloud& dc, Field& local_values);
void update_halo(const DistributedCloud& dc, std::vector<Index>& local_values);
void update_halo(const DistributedCloud& dc, std::vector<char>& local_values);

/// Nodes that reach a seed along directed edges (i -> j in local indices, i owned), closed
/// over the ranks: seeds and reach of halo nodes are their owners'. Collective; serial
/// clouds (one rank) need no exchange.
std::vector<char> reach_over_ranks(const DistributedCloud& dc, std::span<const Index> edge_offsets,
                                   std::span<const Index> edge_targets, std::vector<char> seeds);

/// length_scale of the whole cloud from every rank's part (collective; a part may be empty).
Real length_scale(const PointCloud& part, const Communicator& comm);
/// The same over the particles with counted[i] != 0 only (e.g. the owned ones: a periodic
/// box's images lie outside the box and would lengthen it).
Real length_scale(const PointCloud& part, std::span<const char> counted, const Communicator& comm);

}  // namespace vrsph
