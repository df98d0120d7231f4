// SPDX-License-Identifier: BSD-3-Clause
// The partition every build has: the whole cloud on one process (partition.hpp), and the
// dispatch to the ranks' partition of an MPI build.
#include <algorithm>
#include <limits>
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/neighbours/periodic.hpp>
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
  bool has_halo() const override { return false; }
};

// One process, a box periodic along some axes: the cloud and, as its halo, the images of the
// particles within the halo width of a periodic face (periodic.hpp). Every original is owned;
// an image's global number is its original's, and an exchange copies the original's value.
class PeriodicCloud final : public Partition {
 public:
  PeriodicCloud(const PointCloud& cloud, Real halo_width) : Partition(Communicator()), chunk_(cloud) {
    global_size_ = cloud.size();
    widen(halo_width);
  }
  void widen(Real halo_width) override {
    halo_width_ = halo_width;
    images_ = periodic_images(chunk_, halo_width_);
    local_ = &images_.cloud;
    ids_ = &images_.image_of;
    owned_.assign(static_cast<std::size_t>(images_.cloud.size()), 0);
    std::fill(owned_.begin(), owned_.begin() + chunk_.size(), 1);
  }
  Field to_local(const Field& v) const override { return images_.expand(v); }
  Eigen::MatrixXd to_local(const Eigen::MatrixXd& v) const override { return images_.expand(v); }
  Field to_chunk(Field v) const override { return v.head(chunk_.size()); }
  void update_halo(Field& v) const override { v = images_.expand(Field(v.head(chunk_.size()))); }
  void update_halo(std::vector<Index>& v) const override {
    for (Index i = chunk_.size(); i < local_size(); ++i)
      v[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(images_.image_of[static_cast<std::size_t>(i)])];
  }
  // An edge to an image is an edge to its original; the images take their originals' flags.
  std::vector<char> reach(std::span<const Index> offsets, std::span<const Index> targets,
                          std::vector<char> seeds) const override {
    std::vector<Index> to_original(targets.begin(), targets.end());
    for (Index& j : to_original) j = images_.image_of[static_cast<std::size_t>(j)];
    std::vector<char> r = reaching(offsets, to_original, std::move(seeds));
    for (Index i = chunk_.size(); i < local_size(); ++i)
      r[static_cast<std::size_t>(i)] = r[static_cast<std::size_t>(images_.image_of[static_cast<std::size_t>(i)])];
    return r;
  }

 private:
  const PointCloud& chunk_;
  PeriodicImages images_;
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
  // Under MPI a periodic box's images are halo entries of the ranks' partition.
  if (comm.distributed()) return partition_over_ranks(chunk, halo_width, comm);
#endif
  if (chunk.domain.any_periodic()) return std::make_unique<PeriodicCloud>(chunk, halo_width);
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
