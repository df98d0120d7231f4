// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vector>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>

namespace vrsph {

namespace {
struct Accumulator {
  ErrorNorms n;
  Real wsum = 0, wsq = 0, sq = 0;
  void add(Index i, Real e, Real w) {
    if (n.worst < 0 || e > n.linf) {
      n.linf = e;
      n.worst = i;
    }
    ++n.count;
    wsum += w;
    wsq += w * e * e;
    sq += e * e;
  }
  ErrorNorms finish() {
    n.volume_sum = wsum;
    n.volume_square_sum = wsq;
    n.square_sum = sq;
    if (n.count > 0) {
      n.l2 = wsum > 0 ? std::sqrt(wsq / wsum) : 0;
      n.rms = std::sqrt(sq / static_cast<Real>(n.count));
    }
    return n;
  }
};
}  // namespace

namespace {
ErrorNorms reduce_norms(const ErrorNorms& mine, const Communicator& comm, Index first_id) {
  ErrorNorms n;
  std::vector<double> sums{mine.volume_sum, mine.volume_square_sum, mine.square_sum};
  sum_over_ranks(comm, sums);
  n.count = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(mine.count)));
  const auto [linf, worst] = max_location_over_ranks(comm, mine.count > 0 ? mine.linf : -1.0,
                                                     mine.worst >= 0 ? static_cast<long long>(first_id) + mine.worst : -1);
  n.volume_sum = sums[0];
  n.volume_square_sum = sums[1];
  n.square_sum = sums[2];
  if (n.count > 0) {
    n.linf = linf;
    n.worst = static_cast<Index>(worst);
    n.l2 = n.volume_sum > 0 ? std::sqrt(n.volume_square_sum / n.volume_sum) : 0;
    n.rms = std::sqrt(n.square_sum / static_cast<Real>(n.count));
  }
  return n;
}
}  // namespace

ErrorReport reduce_over_ranks(const ErrorReport& mine, const Communicator& comm, Index first_id) {
  if (!comm.distributed()) return mine;
  return {reduce_norms(mine.all, comm, first_id), reduce_norms(mine.interior, comm, first_id),
          reduce_norms(mine.near_boundary, comm, first_id)};
}

namespace {
// `wall`: per particle, the distance to the nearest tagged boundary particle (used without a
// known domain; null: from the cloud's own). `first_id` numbers the particles in messages.
ErrorReport norms(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& cloud, Real near_distance,
                  std::span<const Real> volumes, const std::vector<Real>* wall_given, Index first_id) {
  check<InputError>(err.rows() == cloud.size() && static_cast<Index>(rows.size()) == cloud.size(),
                    "error_norms: error matrix, row mask and cloud sizes differ");
  check<InputError>(volumes.empty() || static_cast<Index>(volumes.size()) == cloud.size(),
                    "error_norms: volumes size differs from the cloud size");
  // The per-particle part (a norm and a signed distance) in parallel; the sums in particle
  // order on one thread, so the norms do not depend on the thread count.
  const Index n = cloud.size();
  std::vector<Real> e(static_cast<std::size_t>(n));
  std::vector<char> is_near(static_cast<std::size_t>(n));
  // Distance to the boundary: the domain's where it is known, else to the nearest tagged
  // boundary particle (a user's cloud from a file).
  const bool known_domain = cloud.domain.shape != Domain::Shape::None;
  const std::vector<Real> wall = known_domain || wall_given ? std::vector<Real>{} : distance_to_tagged_boundary(cloud);
  const std::vector<Real>& to_wall = wall_given ? *wall_given : wall;
#pragma omp parallel for schedule(static) if (n > 4096)
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (!rows[si]) continue;
    e[si] = err.row(i).norm();
    is_near[si] = (known_domain ? cloud.domain.signed_distance(cloud.positions[si]) : to_wall[si]) < near_distance;
  }
  Accumulator all, inner, near;
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (!rows[si]) continue;
    check<InputError>(std::isfinite(e[si]), "error at particle ", first_id + i, " is not finite");
    const Real w = volumes.empty() ? 1.0 : volumes[si];
    all.add(i, e[si], w);
    (is_near[si] ? near : inner).add(i, e[si], w);
  }
  return {all.finish(), inner.finish(), near.finish()};
}

}  // namespace

ErrorReport error_norms(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& cloud,
                        Real near_distance, std::span<const Real> volumes) {
  return norms(err, rows, cloud, near_distance, volumes, nullptr, 0);
}

void remove_periodic_constant(Eigen::MatrixXd& err, const PointCloud& part, const Communicator& comm) {
  const long long boundary = sum_over_ranks(comm, static_cast<long long>(part.count(Tag::Dirichlet) + part.count(Tag::Neumann)));
  if (!any_rank(comm, part.size() > 0 && part.domain.fully_periodic()) || boundary > 0) return;
  const long long n = sum_over_ranks(comm, static_cast<long long>(part.size()));
  for (Index c = 0; c < err.cols(); ++c) {
    const Real mean = sum_over_ranks(comm, err.col(c).sum()) / static_cast<Real>(std::max<long long>(1, n));
    err.col(c).array() -= mean;
  }
}

ErrorReport error_norms_over_ranks(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& part,
                                   Real near_distance, std::span<const Real> volumes, const Communicator& comm,
                                   Index first_id) {
  if (!comm.distributed()) return error_norms(err, rows, part, near_distance, volumes);
  // Without a known domain, the distances to the tagged boundary particles of every rank
  // (gathered on each: a surface's worth of particles).
  std::vector<Real> wall;
  const bool known_domain = any_rank(comm, part.domain.shape != Domain::Shape::None);
  if (!known_domain) {
    std::vector<double> mine;
    for (Index i = 0; i < part.size(); ++i) {
      const Tag t = part.tags[static_cast<std::size_t>(i)];
      if (t != Tag::Dirichlet && t != Tag::Neumann) continue;
      const Vec3& x = part.positions[static_cast<std::size_t>(i)];
      mine.insert(mine.end(), {x[0], x[1], x[2]});
    }
    const std::vector<double> all = gather_over_ranks(comm, mine);
    std::vector<Vec3> boundary;
    for (std::size_t k = 0; k < all.size(); k += 3) boundary.emplace_back(all[k], all[k + 1], all[k + 2]);
    wall = distance_to_points(boundary, std::max(part.dim, 1), part.positions);
  }
  ErrorReport mine;
  collective(comm, [&] { mine = norms(err, rows, part, near_distance, volumes, known_domain ? nullptr : &wall, first_id); });
  return reduce_over_ranks(mine, comm, first_id);
}

}  // namespace vrsph
