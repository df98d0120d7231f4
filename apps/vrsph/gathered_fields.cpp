// SPDX-License-Identifier: BSD-3-Clause
#include "gathered_fields.hpp"

namespace vrsph::cli {

namespace {

// Every rank's vectors of `width` values per particle, concatenated in rank order.
template <class Get>
std::vector<double> gather_rows(const Communicator& comm, Index count, int width, Get get) {
  std::vector<double> mine(static_cast<std::size_t>(count) * static_cast<std::size_t>(width));
  for (Index i = 0; i < count; ++i)
    for (int c = 0; c < width; ++c) mine[static_cast<std::size_t>(i * width + c)] = get(i, c);
  return gather_over_ranks(comm, mine);
}

}  // namespace

WholeFields gather_whole(const Communicator& comm, const PointCloud& part, const std::vector<PointField>& fields) {
  if (!comm.distributed()) return {part, fields};
  WholeFields whole;
  PointCloud& cloud = whole.cloud;
  cloud.dim = part.dim;
  cloud.spacing = part.spacing;
  cloud.domain = part.domain;
  const Index n = part.size();
  const std::vector<double> x = gather_rows(comm, n, 3, [&](Index i, int c) { return part.positions[static_cast<std::size_t>(i)][c]; });
  const std::vector<double> tag =
      gather_rows(comm, n, 1, [&](Index i, int) { return static_cast<double>(part.tags[static_cast<std::size_t>(i)]); });
  const auto total = static_cast<Index>(tag.size());
  cloud.positions.resize(static_cast<std::size_t>(total));
  cloud.tags.resize(static_cast<std::size_t>(total));
  for (Index i = 0; i < total; ++i) {
    const auto si = static_cast<std::size_t>(i);
    cloud.positions[si] = Vec3(x[3 * si], x[3 * si + 1], x[3 * si + 2]);
    cloud.tags[si] = static_cast<Tag>(static_cast<int>(tag[si]));
  }
  if (any_rank(comm, part.has_normals())) {
    const std::vector<double> nn = gather_rows(comm, n, 3, [&](Index i, int c) {
      return part.has_normals() ? part.normals[static_cast<std::size_t>(i)][c] : 0.0;
    });
    cloud.normals.resize(static_cast<std::size_t>(total));
    for (std::size_t i = 0; i < cloud.normals.size(); ++i) cloud.normals[i] = Vec3(nn[3 * i], nn[3 * i + 1], nn[3 * i + 2]);
  }
  for (const PointField& f : fields) {
    const int width = static_cast<int>(f.values.cols());
    const std::vector<double> v = gather_rows(comm, n, width, [&](Index i, int c) { return f.values(i, c); });
    PointField g{f.name, Eigen::MatrixXd(total, width)};
    for (Index i = 0; i < total; ++i)
      for (int c = 0; c < width; ++c) g.values(i, c) = v[static_cast<std::size_t>(i * width + c)];
    whole.fields.push_back(std::move(g));
  }
  return whole;
}

}  // namespace vrsph::cli
