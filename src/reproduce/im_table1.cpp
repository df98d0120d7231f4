// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <vrsph/reproduce/im_table1.hpp>
#include <vrsph/analysis/plane_wave_multiplier.hpp>
#include <vrsph/cloud/im_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/core/stopwatch.hpp>
#include <vrsph/kernels/reference_weight.hpp>
#include <vrsph/methods/gpm/gpm_pairs.hpp>

namespace vrsph {

namespace {
constexpr Real two_pi = 2 * std::numbers::pi;


// One (level, m): the errors of every requested weight at the evaluation points.
struct LevelCloud {
  PointCloud cloud;
  long long first = 0, per_axis = 0;
  std::vector<Index> points;  // evaluation particles (in Omega)
  Index in_omega = 0;
  // ImVolumes::Cells: the cell length along an axis per lattice index (empty: uniform volumes)
  std::vector<Real> cell_length;
  Real interior_volume = 0;  // V_i of the particles around Omega
};

LevelCloud make_level(const ImTable1Options& o, int level) {
  LevelCloud L;
  ImCloudSpec spec;
  spec.dim = o.dim;
  spec.dx = std::ldexp(1.0, -level);
  spec.seed = o.seed;
  L.cloud = im_cloud(spec);
  check_memory_estimate(static_cast<double>(L.cloud.size()) * sizeof(Real), "the function values of the [IM] cloud",
                        "use fewer --levels");
  long long last = 0;
  im_lattice_range(spec.dx, spec.margin, L.first, last);
  L.per_axis = last - L.first + 1;
  L.interior_volume = L.cloud.domain.measure() / static_cast<Real>(L.cloud.size());
  if (o.volumes == ImVolumes::Cells) {
    // [(i - 1/2) dx, (i + 1/2) dx], the first and last stretched to -H and 1 + H: a tiling of Omega_H.
    L.cell_length.assign(static_cast<std::size_t>(L.per_axis), spec.dx);
    L.cell_length.front() = (static_cast<Real>(L.first) + 0.5) * spec.dx + spec.margin;
    L.cell_length.back() = 1 + spec.margin - (static_cast<Real>(last) - 0.5) * spec.dx;
    L.interior_volume = std::pow(spec.dx, o.dim);
  }
  for (Index p = 0; p < L.cloud.size(); ++p) {
    const Vec3& x = L.cloud.positions[static_cast<std::size_t>(p)];
    bool inside = true;
    for (int k = 0; k < o.dim; ++k) inside = inside && x[k] > 0 && x[k] < 1;
    if (inside) L.points.push_back(p);
  }
  L.in_omega = static_cast<Index>(L.points.size());
  if (L.in_omega > o.max_points) {  // a seeded subset, the same for every m and weight
    std::mt19937_64 rng(o.seed * 7919 + static_cast<std::uint64_t>(level));
    std::shuffle(L.points.begin(), L.points.end(), rng);
    L.points.resize(static_cast<std::size_t>(o.max_points));
    std::sort(L.points.begin(), L.points.end());
  }
  return L;
}
}  // namespace

ImVolumes parse_im_volumes(const std::string& name, const char* option) {
  if (name == "uniform") return ImVolumes::Uniform;
  if (name == "cells") return ImVolumes::Cells;
  throw ConfigError(detail::concat(option, " must be uniform (|Omega_H| / N, [IM] 5.4) or cells (the lattice cells), got '", name, "'"));
}

Real im_theoretical_order(const std::string& weight, int m) {
  if (m <= 1) return std::numeric_limits<Real>::quiet_NaN();
  const int n = weight.back() == '3' ? 3 : 1;
  const int k = reference_weight_operator(weight) == WeightOperator::Laplacian ? 2 : 1;
  return std::min(m - k, n + 1);
}

namespace {
// The errors of one (level, h) over the evaluation points, one per weight, and the pairs
// visited: the window of lattice neighbours around each point, every weight at once.
struct LevelErrors {
  std::vector<Real> err;
  long long pairs = 0;
};

LevelErrors level_errors(const LevelCloud& L, const std::vector<ReferenceWeight>& weights,
                         const std::vector<WeightOperator>& ops, const std::vector<Real>& u, Real h, int d) {
  const Real dx = L.cloud.spacing;
  // V of lattice point q = (a, b, c)
  auto volume = [&L, d](long long a, long long b, long long c) {
    if (L.cell_length.empty()) return L.interior_volume;
    Real v = L.cell_length[static_cast<std::size_t>(a)];
    if (d > 1) v *= L.cell_length[static_cast<std::size_t>(b)];
    if (d > 2) v *= L.cell_length[static_cast<std::size_t>(c)];
    return v;
  };
  const auto window = static_cast<long long>(std::ceil(h / dx)) + 1;
  const std::size_t nw = weights.size();
  LevelErrors out;
  out.err.assign(nw, 0);
#pragma omp parallel
  {
    std::vector<Real> value(nw), lap(nw), local_err(nw, 0);
    std::vector<Vec3> grad(nw);
    long long local_pairs = 0;
#pragma omp for schedule(dynamic, 16)
    for (std::size_t e = 0; e < L.points.size(); ++e) {
      const Index p = L.points[e];
      const Vec3& x = L.cloud.positions[static_cast<std::size_t>(p)];
      const Real up = u[static_cast<std::size_t>(p)];
      std::fill(value.begin(), value.end(), 0.0);
      std::fill(lap.begin(), lap.end(), 0.0);
      std::fill(grad.begin(), grad.end(), Vec3::Zero());
      long long idx[3] = {0, 0, 0}, rest = p;
      for (int k = 0; k < d; ++k) idx[k] = rest % L.per_axis, rest /= L.per_axis;
      long long lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
      for (int k = 0; k < d; ++k) lo[k] = std::max(0LL, idx[k] - window), hi[k] = std::min(L.per_axis - 1, idx[k] + window);
      for (long long c = lo[2]; c <= hi[2]; ++c)
        for (long long b = lo[1]; b <= hi[1]; ++b)
          for (long long a = lo[0]; a <= hi[0]; ++a) {
            const auto q = static_cast<std::size_t>(a + L.per_axis * (b + L.per_axis * c));
            const Vec3 xji = L.cloud.positions[q] - x;
            const Real r = xji.norm();
            if (r >= h) continue;
            ++local_pairs;
            const Real V = volume(a, b, c);
            const Real du = u[q] - up;
            for (std::size_t w = 0; w < nw; ++w) {
              const Real wv = weights[w].value(r, h);
              switch (ops[w]) {
                case WeightOperator::Interpolant: value[w] += gpm::value_weight(V, wv) * u[q]; break;
                case WeightOperator::Gradient: if (r > 0) grad[w] += gpm::gradient_weight(d, V, wv, r, xji) * du; break;
                case WeightOperator::Laplacian: if (r > 0) lap[w] += gpm::laplacian_weight(d, V, wv, r) * du;
              }
            }
          }
      const Real c = std::cos(two_pi * x.sum());
      Vec3 exact_grad = Vec3::Zero();
      for (int k = 0; k < d; ++k) exact_grad[k] = two_pi * c;
      for (std::size_t w = 0; w < nw; ++w) {
        // Relative to the sup norms of v, |grad v| and Delta v: 1, 2 pi sqrt(d), 4 pi^2 d.
        const Real ew = ops[w] == WeightOperator::Interpolant ? std::abs(value[w] - up)
                        : ops[w] == WeightOperator::Gradient
                            ? (grad[w] - exact_grad).norm() / (two_pi * std::sqrt(static_cast<Real>(d)))
                            : std::abs(lap[w] + two_pi * two_pi * d * up) / (two_pi * two_pi * d);
        local_err[w] = std::max(local_err[w], ew);
      }
    }
#pragma omp critical
    {
      for (std::size_t w = 0; w < nw; ++w) out.err[w] = std::max(out.err[w], local_err[w]);
      out.pairs += local_pairs;
    }
  }
  return out;
}

// The observed order against the newest earlier row of the same (weight, m), and the slope
// of log e against log h over up to three earlier levels (e ~ c h^p).
void orders(const std::vector<ImTable1Row>& rows, ImTable1Row& row) {
  row.order = row.order_fit = std::numeric_limits<Real>::quiet_NaN();
  std::vector<const ImTable1Row*> previous;  // the same (weight, m) on earlier levels, newest first
  for (auto it = rows.rbegin(); it != rows.rend() && previous.size() < 3; ++it)
    if (it->weight == row.weight && it->m == row.m) previous.push_back(&*it);
  if (previous.empty()) return;
  row.order = std::log(previous[0]->error_rel / row.error_rel) / std::log(previous[0]->h / row.h);
  Real sx = std::log(row.h), sy = std::log(row.error_rel), sxx = sx * sx, sxy = sx * sy;
  for (const auto* q : previous) {
    const Real x = std::log(q->h), y = std::log(q->error_rel);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const Real k = static_cast<Real>(previous.size() + 1);
  row.order_fit = (k * sxy - sx * sy) / (k * sxx - sx * sx);
}
}  // namespace

std::vector<ImTable1Row> im_table1(const ImTable1Options& o) {
  check<ConfigError>(o.dim >= 1 && o.dim <= 3, "im-table1: dim must be 1, 2 or 3, got ", o.dim);
  check<ConfigError>(!o.weights.empty() && !o.m.empty() && !o.levels.empty(), "im-table1 needs weights, m values and levels");
  check<ConfigError>(o.max_points >= 1, "im-table1: at least one evaluation point");
  std::vector<ReferenceWeight> weights;
  std::vector<WeightOperator> ops;  // once per run, not per pair
  for (const auto& w : o.weights) {
    weights.push_back(reference_weight(w, o.dim));  // ConfigError on unknown names
    ops.push_back(reference_weight_operator(w));
  }
  for (int m : o.m) check<ConfigError>(m >= 1 && m <= 20, "im-table1: m must be in 1..20, got ", m);
  for (int l : o.levels) check<ConfigError>(l >= 2 && l <= 14, "im-table1: levels must be in 2..14 (dx = 2^-level), got ", l);
  const int d = o.dim;
  std::vector<ImTable1Row> rows;
  const double steps = static_cast<double>(o.levels.size() * o.m.size());
  double step = 0;
  for (int level : o.levels) {
    const LevelCloud L = make_level(o, level);
    const Real dx = L.cloud.spacing;
    const Real volume_bias = L.interior_volume / std::pow(dx, d) - 1;
    std::vector<Real> u(L.cloud.positions.size());
#pragma omp parallel for schedule(static)
    for (std::size_t p = 0; p < u.size(); ++p) u[p] = std::sin(two_pi * L.cloud.positions[p].sum());
    for (int m : o.m) {
      const Stopwatch clock;
      const Real h = 2.6 * std::pow(2.0, 5.0 / m - 5) * std::pow(dx, 1.0 / m);
      if (o.progress) o.progress(detail::concat("im-table1: dx = 2^-", level, ", m = ", m, ", h/dx = ", h / dx, ", ",
                                                L.cloud.size(), " particles, ", L.points.size(), " points"), step++ / steps);
      const LevelErrors le = level_errors(L, weights, ops, u, h, d);
      const Real seconds = clock.seconds();
      for (std::size_t w = 0; w < weights.size(); ++w) {
        ImTable1Row row;
        row.weight = o.weights[w];
        row.m = m;
        row.level = level;
        row.dx = dx;
        row.h = h;
        row.particles = L.cloud.size();
        row.evaluated = static_cast<Index>(L.points.size());
        row.in_omega = L.in_omega;
        row.neighbours_mean = static_cast<Real>(le.pairs) / static_cast<Real>(L.points.size());
        row.error_rel = le.err[w];
        row.volume_bias = volume_bias;
        const Real mu = plane_wave_multiplier(weights[w], ops[w], two_pi * std::sqrt(Real(d)) * h);
        row.error_integral = std::abs(1 - (1 + volume_bias) * mu);
        orders(rows, row);
        row.seconds = seconds;
        rows.push_back(row);
      }
    }
  }
  return rows;
}

}  // namespace vrsph
