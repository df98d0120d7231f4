// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/stencil/apply.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/analysis/stability.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/methods/spe/ingredients.hpp>
#include <vrsph/neighbours/search.hpp>
#include "../cloud/random.hpp"

namespace vrsph {

namespace {
void validate(const StabilityParams& p) {
  check_study_settings(p.dim, p.support_factor, p.delta, 0);
  // τ is the stability number ν = Δt/ℓ² of one explicit step; the bounds of interest are
  // 0.25-0.4, and beyond 1 every scheme is unstable (issue 11 asks for (0, 1]).
  check<ConfigError>(std::isfinite(p.tau) && p.tau > 0 && p.tau <= 1, "--tau must be in (0, 1], got ", p.tau);
  check<ConfigError>(p.k_samples >= 1 && p.k_samples <= 256, "wave vectors per direction must be 1..256, got ", p.k_samples);
  check<ConfigError>(p.n >= 2 && p.n <= 400, "stability analysis: n must be 2..400 (a dense sweep over k), got ", p.n);
  check<ConfigError>(p.cloud == CloudFamily::Uniform || p.cloud == CloudFamily::Perturbed,
                     "stability analysis: --cloud uniform or perturbed");
  check<ConfigError>(!p.methods.empty(), "no method given");
  check_support_is_local(p.support_factor / p.n, std::sqrt(static_cast<Real>(p.dim)), p.support_factor);
  // Work: particles x neighbours x wave vectors complex exponentials; refuse sweeps of hours.
  const double particles = std::pow(p.n + 1.0, p.dim), waves = std::pow(static_cast<double>(p.k_samples), p.dim);
  const double neighbours = p.dim == 1 ? 2 * p.support_factor
                                       : p.dim == 2 ? std::numbers::pi * p.support_factor * p.support_factor
                                                    : 4.2 * std::pow(p.support_factor, 3);
  check<ConfigError>(particles * waves * neighbours < 2e10, "stability analysis of ", particles, " particles x ", waves,
                     " wave vectors x ~", neighbours, " neighbours is too large a sweep (limit 2e10 terms): lower --n, "
                     "--k or --h-factor");
  for (const auto& m : p.methods) {
    check<ConfigError>(builtin_methods().info(m).supports(OperatorKind::Laplacian), "method ", m,
                       " does not provide a Laplacian");
    (void)builtin_methods().create(m, options_for(p.method_options, m));
  }
}
}  // namespace

namespace {
// Wave vectors k = (π/dx)(-1 + (2 a + 1)/K) per direction: symmetric, excluding ±π/dx twice.
std::vector<Vec3> wave_vectors(int dim, int K, Real dx) {
  std::vector<Vec3> waves;
  const auto component = [&](int a) { return std::numbers::pi / dx * (-1 + (2.0 * a + 1) / K); };
  for (int a = 0; a < K; ++a)
    for (int b = 0; b < (dim > 1 ? K : 1); ++b)
      for (int c = 0; c < (dim > 2 ? K : 1); ++c)
        waves.emplace_back(component(a), dim > 1 ? component(b) : 0, dim > 2 ? component(c) : 0);
  return waves;
}

// Particles within one support of a face: their rows are the boundary's.
std::vector<char> near_faces(const PointCloud& cloud, int dim, Real support) {
  std::vector<char> boundary(static_cast<std::size_t>(cloud.size()), 0);
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int k = 0; k < dim; ++k)
      if (x[k] < support || 1 - x[k] < support) boundary[static_cast<std::size_t>(i)] = 1;
  }
  return boundary;
}

// Per particle j, over the waves: max |λ| and max |Im λ| of the amplification factor
// λ = 1 + scale Σ_J L_jJ e^{i k·(x_J - x_j)}; the kept λ (every stride-th particle) in `row`.
void amplification(const PointCloud& cloud, const Stencil& L, const std::vector<Vec3>& waves, Real scale,
                   const std::vector<char>& boundary, bool keep, std::size_t stride, std::vector<Real>& worst,
                   std::vector<Real>& imag, StabilityRow& row) {
#pragma omp parallel for schedule(dynamic, 64)
  for (Index j = 0; j < cloud.size(); ++j) {
    const auto sj = static_cast<std::size_t>(j);
    const Vec3& xj = cloud.positions[sj];
    for (std::size_t w = 0; w < waves.size(); ++w) {
      std::complex<Real> sum = 0;
      for (Index e = L.row_begin(j); e < L.row_end(j); ++e) {
        const auto J = static_cast<std::size_t>(L.col[static_cast<std::size_t>(e)]);
        const Real phase = waves[w].dot(cloud.positions[J] - xj);
        sum += L.values[0][static_cast<std::size_t>(e)] * std::complex<Real>(std::cos(phase), std::sin(phase));
      }
      const std::complex<Real> lambda = 1.0 + scale * sum;
      worst[sj] = std::max(worst[sj], std::abs(lambda));
      imag[sj] = std::max(imag[sj], std::abs(lambda.imag()));
      if (keep && sj % stride == 0) {
        row.samples[sj / stride * waves.size() + w] = lambda;
        row.sample_is_boundary[sj / stride * waves.size() + w] = boundary[sj];
      }
    }
  }
}

// The row's maxima over the interior and the boundary particles.
void summarise(const std::vector<Real>& worst, const std::vector<Real>& imag, const std::vector<char>& boundary,
               StabilityRow& row) {
  for (std::size_t sj = 0; sj < worst.size(); ++sj) {
    row.max_abs = std::max(row.max_abs, worst[sj]);
    row.max_imag = std::max(row.max_imag, imag[sj]);
    const bool unstable = worst[sj] > 1 + 1e-12;
    if (boundary[sj]) {
      row.max_abs_boundary = std::max(row.max_abs_boundary, worst[sj]);
      row.unstable_boundary += unstable;
    } else {
      ++row.interior;
      row.max_abs_interior = std::max(row.max_abs_interior, worst[sj]);
      row.max_imag_interior = std::max(row.max_imag_interior, imag[sj]);
      row.unstable_interior += unstable;
    }
  }
}
}  // namespace

StabilityResult run_stability(const StabilityParams& p) {
  validate(p);
  CloudSpec spec;
  spec.family = p.cloud;
  spec.box = Domain::unit_box(p.dim);
  spec.n = p.n;
  spec.layout = p.layout;
  spec.delta = p.delta;
  spec.seed = p.seed;
  const StudyCloud sc = make_study_cloud(spec);
  const PointCloud& cloud = sc.cloud;
  StabilityResult r;
  r.params = p;
  r.dx = sc.dx;
  const Real support = p.support_factor * sc.dx;
  r.smoothing_length = support / kernel_info(p.kernel).support_per_smoothing_length;
  SearchParams sp;
  sp.radius = support;
  const NeighbourList nl = find_neighbours(cloud, sp);
  const Discretisation disc{cloud, nl, p.kernel, sc.dx};
  std::vector<char> rows(static_cast<std::size_t>(cloud.size()), 1);
  const std::vector<char> boundary = near_faces(cloud, p.dim, support);
  const std::vector<Vec3> waves = wave_vectors(p.dim, p.k_samples, sc.dx);
  const Real scale = p.tau * r.smoothing_length * r.smoothing_length;
  for (const auto& name : p.methods) {
    const auto method = builtin_methods().create(name, options_for(p.method_options, name));
    StencilRequest req{OperatorKind::Laplacian};
    req.rows = rows;
    const Stencil L = method->build(disc, req);
    require_point_rows(L, "the stability study");
    StabilityRow row;
    row.method = name;
    row.particles = cloud.size();
    std::vector<Real> worst(static_cast<std::size_t>(cloud.size()), 0);
    std::vector<Real> imag(static_cast<std::size_t>(cloud.size()), 0);
    // Kept λ for plots: every particle's, or every stride-th particle's beyond 2e6 values.
    const std::size_t total = static_cast<std::size_t>(cloud.size()) * waves.size();
    const std::size_t stride = std::max<std::size_t>(1, total / 2000000 + (total % 2000000 != 0 && total > 2000000));
    if (p.keep_samples) {
      row.samples.resize((static_cast<std::size_t>(cloud.size()) / stride + 1) * waves.size());
      row.sample_is_boundary.resize(row.samples.size());
    }
    amplification(cloud, L, waves, scale, boundary, p.keep_samples, stride, worst, imag, row);
    summarise(worst, imag, boundary, row);
    if (p.keep_samples) {  // drop the unused tail slots
      const std::size_t used = (static_cast<std::size_t>(cloud.size() - 1) / stride + 1) * waves.size();
      row.samples.resize(used);
      row.sample_is_boundary.resize(used);
    }
    r.rows.push_back(std::move(row));
  }
  return r;
}

Table to_table(const StabilityResult& r) {
  Table t;
  t.columns = {"method", "particles", "interior", "tau", "max_abs", "max_abs_interior", "max_abs_boundary", "max_imag",
               "max_imag_interior", "unstable_interior", "unstable_boundary"};
  for (const auto& row : r.rows)
    t.add_row({{"method", row.method},
               {"particles", static_cast<long long>(row.particles)},
               {"interior", static_cast<long long>(row.interior)},
               {"tau", r.params.tau},
               {"max_abs", row.max_abs},
               {"max_abs_interior", row.interior ? row.max_abs_interior : std::nan("")},
               {"max_abs_boundary", row.max_abs_boundary},
               {"max_imag", row.max_imag},
               {"max_imag_interior", row.interior ? row.max_imag_interior : std::nan("")},
               {"unstable_interior", static_cast<long long>(row.unstable_interior)},
               {"unstable_boundary", static_cast<long long>(row.unstable_boundary)}});
  return t;
}

std::vector<XiStatisticsRow> xi_statistics(int dim, const std::vector<int>& counts, int configurations,
                                           std::uint64_t seed) {
  check<ConfigError>(dim == 2 || dim == 3, "ξ statistics: dimension 2 or 3, got ", dim);
  check<ConfigError>(configurations >= 2 && configurations <= 100000, "ξ statistics: configurations must be "
                     "2..100000, got ", configurations);
  // Up front: every configuration draws and evaluates m neighbours (~1e-7 s each here).
  double work = 0;
  for (int m : counts) work += static_cast<double>(configurations) * std::max(m, 0);
  check<ConfigError>(work <= 2e9, "ξ statistics: ", configurations, " configurations x ", work / configurations,
                     " neighbours = ", work, " neighbour evaluations (minutes to hours); lower --configurations or "
                     "--neighbours (at most 2e9)");
  const Real measure = dim == 2 ? std::numbers::pi : 4 * std::numbers::pi / 3;
  const Kernel ker(KernelType::CubicSplineSPE, dim, 2.0);  // h̃ = 1, support 2
  std::vector<XiStatisticsRow> out;
  for (int m : counts) {
    check<ConfigError>(m >= dim && m <= 100000, "ξ statistics: neighbour count must be ", dim, "..100000, got ", m);
    std::vector<Real> xi(static_cast<std::size_t>(configurations));
#pragma omp parallel for schedule(dynamic, 1)
    for (int c = 0; c < configurations; ++c) {
      spe::RowGeometry row;
      row.dim = dim;
      row.resize(static_cast<std::size_t>(m));
      row.volume_self = measure / m;
      row.W_self = ker.W(0);
      const std::uint64_t stream = static_cast<std::uint64_t>(m) * 1000003u + static_cast<std::uint64_t>(c);
      std::uint64_t counter = 0;
      for (int k = 0; k < m; ++k) {
        Vec3 x;
        do {  // uniform in the unit ball by rejection (seeded, thread-count independent)
          x = Vec3::Zero();
          for (int a = 0; a < dim; ++a) x[a] = 2 * detail::uniform01(seed, stream, counter++) - 1;
        } while (x.squaredNorm() >= 1 || x.squaredNorm() == 0);
        const auto sk = static_cast<std::size_t>(k);
        row.delta[sk] = x;
        row.r[sk] = x.norm();
        row.volume[sk] = measure / m;
        row.W[sk] = ker.W(row.r[sk]);
        row.dW_over_r[sk] = ker.dW_over_r(row.r[sk]);
      }
      spe::RowIngredients in;
      spe::compute_ingredients(row, spe::GradientOption::G1, in);
      xi[static_cast<std::size_t>(c)] = std::isfinite(in.condition) ? in.xi.norm() : std::nan("");
    }
    XiStatisticsRow s;
    s.neighbours = m;
    Index valid = 0;
    for (Real v : xi)
      if (std::isfinite(v)) {
        s.mean += v;
        s.max = std::max(s.max, v);
        ++valid;
      }
    s.mean /= static_cast<Real>(std::max<Index>(valid, 1));
    for (Real v : xi)
      if (std::isfinite(v)) s.std += (v - s.mean) * (v - s.mean);
    s.std = valid > 1 ? std::sqrt(s.std / static_cast<Real>(valid - 1)) : 0;
    out.push_back(s);
  }
  return out;
}

Table to_table(const std::vector<XiStatisticsRow>& rows) {
  Table t;
  t.columns = {"sets", "neighbours", "xi_mean", "xi_std", "xi_max"};
  for (const auto& r : rows)
    t.add_row({{"sets", std::string("random, unit disc")},
               {"neighbours", static_cast<long long>(r.neighbours)},
               {"xi_mean", r.mean},
               {"xi_std", r.std},
               {"xi_max", r.max}});
  return t;
}

}  // namespace vrsph
