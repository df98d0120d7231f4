// SPDX-License-Identifier: BSD-3-Clause
// The partition every build has: the whole cloud on one process (partition.hpp), and the
// dispatch to the ranks' partition of an MPI build.
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include "../core/reachability.hpp"
#include "partition.hpp"

namespace vrsph::detail {

namespace {
class WholeCloud final : public Partition {
 public:
  explicit WholeCloud(const PointCloud& cloud) : Partition(Communicator()) {
    local_ = &cloud;
    owned_.assign(static_cast<std::size_t>(cloud.size()), 1);
    global_size_ = cloud.size();
    halo_width_ = std::numeric_limits<Real>::infinity();
  }
  void widen(Real) override {}
  Field to_local(const Field& v) const override { return v; }
  Eigen::MatrixXd to_local(const Eigen::MatrixXd& v) const override { return v; }
  Field to_chunk(Field v) const override { return v; }
  void update_halo(Field&) const override {}
  void update_halo(std::vector<Index>&) const override {}
  std::vector<char> reach(std::span<const Index> offsets, std::span<const Index> targets,
                          std::vector<char> seeds) const override {
    return reaching(offsets, targets, std::move(seeds));
  }
};
}  // namespace

void Partition::stage(const std::function<void()>& run) const {
  if (!distributed()) return run();  // local numbers are the global ones
  collective(comm_, [&] {
    try {
      run();
    } catch (const std::exception& e) {
      rethrow_with_message(e, renumber_particles(e.what(), [&](long long i) {
                             return i < local_size() ? global_id(static_cast<Index>(i)) : i;
                           }));
    }
  });
}

std::unique_ptr<Partition> make_partition(const PointCloud& chunk, Real halo_width, const Communicator& comm) {
#if VRSPH_HAVE_MPI
  if (comm.distributed()) return partition_over_ranks(chunk, halo_width, comm);
#endif
  (void)halo_width;
  (void)comm;
  return std::make_unique<WholeCloud>(chunk);
}

Real spacing_over_ranks(const PointCloud& chunk, const Communicator& comm) {
#if VRSPH_HAVE_MPI
  if (comm.distributed()) return estimate_spacing_over_ranks(chunk, comm);
#endif
  (void)comm;
  return estimate_spacing(chunk);
}

}  // namespace vrsph::detail
