// SPDX-License-Identifier: BSD-3-Clause
#include <chrono>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vrsph/reproduce/spectrum.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

namespace {

Spectrum spectrum_of(const Eigen::MatrixXd& minus_k, const std::string& what) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(minus_k, false);
  check<NumericalError>(es.info() == Eigen::Success, "eigensolver did not converge for ", what, " (",
                        minus_k.rows(), " unknowns)");
  const Eigen::VectorXcd lambda = es.eigenvalues();
  std::vector<std::complex<Real>> sorted(lambda.data(), lambda.data() + lambda.size());
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.real() < b.real(); });
  Spectrum out;
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const auto l = sorted[k];
    const Real mode = static_cast<Real>(k + 1) * std::numbers::pi;
    out.omega_ratio.push_back(l.real() >= 0 ? std::sqrt(l.real()) / mode : std::nan(""));
    if (l.real() < 0) ++out.negative;
    if (std::abs(l) > 0) out.max_imag_relative = std::max(out.max_imag_relative, std::abs(l.imag()) / std::abs(l));
  }
  return out;
}

}  // namespace

Spectrum vibration_spectrum(const SpectrumParams& p) {
  check_spectrum_size(p.n);
  check<ConfigError>(std::isfinite(p.h_factor) && p.h_factor > 0, "h-factor must be positive and finite, got ",
                     p.h_factor);
  check_support_is_local(p.h_factor / p.n, 1.0, p.h_factor);
  const auto method = builtin_methods().create(p.method, p.options);
  check<ConfigError>(method->info().supports(OperatorKind::Laplacian), "method ", p.method,
                     " has no second-derivative stencil");
  CloudSpec spec;
  spec.family = p.cloud;
  spec.box = Domain::unit_box(1);
  spec.n = p.n;
  spec.layout = Layout::Vertex;
  spec.delta = p.delta;
  spec.seed = p.seed;
  const StudyCloud sc = make_study_cloud(spec);
  const PointCloud& cloud = sc.cloud;
  SearchParams sp;
  sp.radius = p.h_factor * sc.dx;
  const NeighbourList nl = find_neighbours(cloud, sp);
  std::vector<char> interior(static_cast<std::size_t>(cloud.size()));
  std::vector<Index> dof(static_cast<std::size_t>(cloud.size()), -1);
  Index m = 0;
  for (Index i = 0; i < cloud.size(); ++i) {
    interior[static_cast<std::size_t>(i)] = cloud.tags[static_cast<std::size_t>(i)] == Tag::Interior;
    if (interior[static_cast<std::size_t>(i)]) dof[static_cast<std::size_t>(i)] = m++;
  }
  StencilRequest req;
  req.kind = OperatorKind::Laplacian;
  req.rows = interior;
  const Stencil K = method->build({cloud, nl, p.kernel, cloud.spacing}, req);
  require_point_rows(K, "the spectrum");
  // Fixed ends: their columns drop out (x = 0 there).
  Eigen::MatrixXd minus_k = Eigen::MatrixXd::Zero(m, m);
  for (Index i = 0; i < cloud.size(); ++i) {
    const Index di = dof[static_cast<std::size_t>(i)];
    if (di < 0) continue;
    for (Index k = K.row_begin(i); k < K.row_end(i); ++k) {
      const Index dj = dof[static_cast<std::size_t>(K.col[static_cast<std::size_t>(k)])];
      if (dj >= 0) minus_k(di, dj) -= K.values[0][static_cast<std::size_t>(k)];
    }
  }
  return spectrum_of(minus_k, "method " + p.method);
}

double dense_spectrum_bytes(int n) {
  // The matrix, its Hessenberg/Schur working copy, and the Householder workspace.
  const double m = n - 1.0;
  return 3.0 * m * m * static_cast<double>(sizeof(Real));
}

double dense_spectrum_seconds(int n) {
  // Real Schur form without vectors: about 10 m^3 flops at the calibrated rate
  // (measured here: m = 999 in 1.1 s on one core).
  const double m = n - 1.0;
  return 10.0 * m * m * m / dense_spectrum_flops_per_second;
}

double calibrated_spectrum_seconds(const SpectrumParams& params) {
  check_spectrum_size(params.n);
  SpectrumParams small = params;
  small.n = std::max(3, params.n / 4);
  const auto start = std::chrono::steady_clock::now();
  (void)vibration_spectrum(small);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double ratio = (params.n - 1.0) / (small.n - 1.0);
  return seconds * ratio * ratio * ratio;
}

void check_spectrum_size(int n) {
  check<ConfigError>(n >= 3 && n <= 5000, "spectrum: n = ", n, " intervals outside 3..5000 (a dense eigenvalue problem)");
  check_memory_estimate(dense_spectrum_bytes(n), detail::concat("the dense eigenvalue problem (", n - 1, " unknowns)"),
                        "reduce --n");
}

Spectrum fem_lumped_spectrum(int n) {
  check_spectrum_size(n);
  const Real dx = 1.0 / n;
  const Index m = n - 1;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  for (Index i = 0; i < m; ++i) {
    a(i, i) = 2 / (dx * dx);
    if (i > 0) a(i, i - 1) = -1 / (dx * dx);
    if (i + 1 < m) a(i, i + 1) = -1 / (dx * dx);
  }
  return spectrum_of(a, "lumped-mass FEM");
}

std::vector<Real> fem_lumped_closed_form(int n) {
  std::vector<Real> out;
  const Real dx = 1.0 / n;
  for (int k = 1; k < n; ++k) {
    const Real t = k * std::numbers::pi * dx / 2;
    out.push_back(std::sin(t) / t);
  }
  return out;
}

}  // namespace vrsph
