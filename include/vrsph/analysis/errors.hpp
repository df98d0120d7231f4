// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Error norms over a set of particles, split into interior and near-boundary ones.
//   L∞  = max_i |e_i|
//   L2  = sqrt(sum_i v_i |e_i|^2 / sum_i v_i)   (volume-weighted, v_i = particle volume)
//   RMS = sqrt(mean_i |e_i|^2)
// For vector errors |e_i| is the Euclidean norm over components (METHODS §5).
#include <span>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph {

struct ErrorNorms {
  Real linf = 0, l2 = 0, rms = 0;
  Index count = 0;
  Index worst = -1;  ///< particle attaining linf
  /// The sums behind l2 and rms (sum of volumes, of volume x error^2, of error^2): what a
  /// reduction over MPI ranks adds up.
  Real volume_sum = 0, volume_square_sum = 0, square_sum = 0;
};

struct ErrorReport {
  ErrorNorms all, interior, near_boundary;
};

/// The norms of the whole cloud from every rank's (collective; serial: unchanged). `first_id`
/// is the global number of this rank's first particle: `worst` becomes a global number.
ErrorReport reduce_over_ranks(const ErrorReport& mine, const Communicator& comm, Index first_id);

/// err: N x c pointwise errors; rows: which particles count; near_distance: particles
/// whose distance to the domain boundary is below it count as near-boundary (use the
/// support radius: their kernels would be truncated without ghosts; without a known domain
/// the distance is to the nearest tagged boundary particle); volumes: N values
/// or empty (equal volumes).
ErrorReport error_norms(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& cloud,
                        Real near_distance, std::span<const Real> volumes = {});

/// On a fully periodic box without boundary particles u is known up to a constant (the solve
/// returns the one with zero mean): removes the mean of err over every rank's particles, so the
/// norms are those of the best constant shift. Elsewhere err is left as it is. Collective.
void remove_periodic_constant(Eigen::MatrixXd& err, const PointCloud& part, const Communicator& comm);

/// error_norms of the whole cloud when each rank passes its part, numbered from `first_id`
/// (collective; serial: error_norms). Without a known domain the near-boundary distance is
/// to the tagged boundary particles of every rank, gathered on each (a surface's worth).
ErrorReport error_norms_over_ranks(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& part,
                                   Real near_distance, std::span<const Real> volumes, const Communicator& comm,
                                   Index first_id);

}  // namespace vrsph
