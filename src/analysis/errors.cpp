#include <cmath>
#include <vrsph/analysis/errors.hpp>
#include <vrsph/core/error.hpp>

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
    if (n.count > 0) {
      n.l2 = wsum > 0 ? std::sqrt(wsq / wsum) : 0;
      n.rms = std::sqrt(sq / static_cast<Real>(n.count));
    }
    return n;
  }
};
}  // namespace

ErrorReport error_norms(const Eigen::MatrixXd& err, std::span<const char> rows, const PointCloud& cloud,
                        Real near_distance, std::span<const Real> volumes) {
  check<InputError>(err.rows() == cloud.size() && static_cast<Index>(rows.size()) == cloud.size(),
                    "error_norms: error matrix, row mask and cloud sizes differ");
  check<InputError>(volumes.empty() || static_cast<Index>(volumes.size()) == cloud.size(),
                    "error_norms: volumes size differs from the cloud size");
  Accumulator all, inner, near;
  for (Index i = 0; i < cloud.size(); ++i) {
    if (!rows[static_cast<std::size_t>(i)]) continue;
    const Real e = err.row(i).norm();
    check<InputError>(std::isfinite(e), "error at particle ", i, " is not finite");
    const Real w = volumes.empty() ? 1.0 : volumes[static_cast<std::size_t>(i)];
    all.add(i, e, w);
    if (cloud.domain.signed_distance(cloud.positions[static_cast<std::size_t>(i)]) < near_distance)
      near.add(i, e, w);
    else
      inner.add(i, e, w);
  }
  return {all.finish(), inner.finish(), near.finish()};
}

}  // namespace vrsph
