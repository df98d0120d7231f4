// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: Partition, the particles one rank of a pipeline works on (owned + halo), and
// every exchange a stage needs, behind one interface. A serial run is the partition of the
// whole cloud over a communicator of one (every particle owned, no halo, each exchange the
// identity); a run under MPI is a Morton partition with a halo (distributed_cloud.hpp).
// The solve pipeline (problem/bvp_*.cpp) is written once against this interface.
#include <functional>
#include <memory>
#include <span>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/config.hpp>
#include <vrsph/parallel/distributed_cloud.hpp>

namespace vrsph::detail {

class Partition {
 public:
  virtual ~Partition() = default;
  const Communicator& comm() const { return comm_; }
  bool distributed() const { return comm_.distributed(); }
  /// Whether local() holds copies of other particles (a rank's halo, periodic images): the
  /// stages then work on owned rows and number columns through global_id.
  virtual bool has_halo() const { return true; }
  /// Owned and halo particles (serial: the whole cloud, not a copy).
  const PointCloud& local() const { return *local_; }
  Index local_size() const { return local_->size(); }
  Index global_size() const { return global_size_; }
  /// Per local particle: 1 if this rank owns it.
  const std::vector<char>& owned() const { return owned_; }
  /// The number a message names: the particle's index in the whole (serial) cloud.
  long long global_id(Index i) const { return ids_ ? (*ids_)[static_cast<std::size_t>(i)] : i; }
  /// Every particle within this distance of an owned one is local (serial: infinity).
  Real halo_width() const { return halo_width_; }

  /// Partitions again with a halo at least this wide (serial: nothing to do).
  virtual void widen(Real halo_width) = 0;
  /// Values of the input chunk at the local particles, and the owned values back in the
  /// chunk's order (serial: copies).
  virtual Field to_local(const Field& chunk_values) const = 0;
  virtual Eigen::MatrixXd to_local(const Eigen::MatrixXd& chunk_values) const = 0;
  virtual Field to_chunk(Field local_values) const = 0;  ///< (serial: moved through)
  /// Halo entries overwritten with their owners' values.
  virtual void update_halo(Field& local_values) const = 0;
  virtual void update_halo(std::vector<Index>& local_values) const = 0;
  /// Nodes that reach a seed along the edges i -> j (CSR over local particles), closed over
  /// the ranks (reach_over_ranks).
  virtual std::vector<char> reach(std::span<const Index> offsets, std::span<const Index> targets,
                                  std::vector<char> seeds) const = 0;
  virtual DistributionStats stats() const { return {}; }

  /// Runs a stage on the local particles: collective (a failure on one rank is the same
  /// typed exception on every rank), and its messages name global particle numbers.
  void stage(const std::function<void()>& run) const;

 protected:
  explicit Partition(const Communicator& comm) : comm_(comm) {}
  Communicator comm_;
  const PointCloud* local_ = nullptr;
  const std::vector<Index>* ids_ = nullptr;  ///< null: the identity
  std::vector<char> owned_;
  Index global_size_ = 0;
  Real halo_width_ = 0;
};

/// The partition of `chunk` (this rank's part of the cloud) over `comm` with a halo of
/// `halo_width`: the whole cloud in serial (the chunk, validated by the caller, must outlive
/// the partition), with the images of the particles within halo_width of its periodic faces
/// when its box is periodic (one rank only, for now).
std::unique_ptr<Partition> make_partition(const PointCloud& chunk, Real halo_width, const Communicator& comm);

/// estimate_spacing of the whole cloud from every rank's chunk (the same value on every rank).
Real spacing_over_ranks(const PointCloud& chunk, const Communicator& comm);

#if VRSPH_HAVE_MPI
// parallel/partition_ranks.cpp (builds with PETSc and MPI).
std::unique_ptr<Partition> partition_over_ranks(const PointCloud& chunk, Real halo_width, const Communicator& comm);
#endif

}  // namespace vrsph::detail
