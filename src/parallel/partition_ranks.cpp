// SPDX-License-Identifier: BSD-3-Clause
// The partition of a run under MPI (partition.hpp): a DistributedCloud, partitioned again
// when a stage needs a wider halo.
#include "partition.hpp"

namespace vrsph::detail {

namespace {
class OverRanks final : public Partition {
 public:
  OverRanks(const PointCloud& chunk, Real halo_width, const Communicator& comm) : Partition(comm), chunk_(chunk) {
    widen(halo_width);
  }
  void widen(Real halo_width) override {
    dc_ = distribute(chunk_, halo_width, comm_);
    local_ = &dc_.local;
    ids_ = &dc_.global_id;
    owned_ = dc_.owned;
    global_size_ = dc_.global_size;
    halo_width_ = dc_.halo_width;
  }
  Field to_local(const Field& v) const override { return chunk_to_local(dc_, v); }
  Eigen::MatrixXd to_local(const Eigen::MatrixXd& v) const override { return chunk_to_local(dc_, v); }
  Field to_chunk(Field v) const override { return local_to_chunk(dc_, v); }
  void update_halo(Field& v) const override { vrsph::update_halo(dc_, v); }
  void update_halo(std::vector<Index>& v) const override { vrsph::update_halo(dc_, v); }
  std::vector<char> reach(std::span<const Index> offsets, std::span<const Index> targets,
                          std::vector<char> seeds) const override {
    return reach_over_ranks(dc_, offsets, targets, std::move(seeds));
  }
  DistributionStats stats() const override { return dc_.stats; }

 private:
  const PointCloud& chunk_;
  DistributedCloud dc_;
};
}  // namespace

std::unique_ptr<Partition> partition_over_ranks(const PointCloud& chunk, Real halo_width, const Communicator& comm) {
  return std::make_unique<OverRanks>(chunk, halo_width, comm);
}

}  // namespace vrsph::detail
