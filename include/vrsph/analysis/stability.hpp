// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Von Neumann analysis of a method's Laplacian ([SPE] §4.3, (81)–(83); METHODS §3.7.9) and
// the statistics of the monotonicity diagnostic ξ ([SPE] Fig. 6).
//
// Growth factor of explicit Euler at particle j for the wave vector k:
//   λ_j(k) = 1 + τ ℓ² Σ_J L_jJ e^{i k·(x_J - x_j)},
// τ dimensionless (METHODS' recommended reading of (83)), ℓ = the kernel's smoothing length
// (support / support-per-smoothing-length, e.g. support/2 for the cubic spline), k sampled on
// a regular grid of [-π/dx, π/dx]^d. Stability needs |λ| <= 1. Every particle's row is built
// (boundary particles with their truncated supports), and the result separates particles
// whose support reaches the domain boundary from the others.
//
// ξ statistics (Fig. 6): m neighbours drawn uniformly in the unit disc (ball) around a centre,
// h̃ = 1 (support 2), volumes |disc|/m, ξ = Cᵀ Ñ with gradient g1; mean and standard deviation
// of |ξ| over `configurations` draws for each m.
#include <complex>
#include <cstdint>
#include <map>
#include <string>
#include <vector>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/io/table.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>

namespace vrsph {

struct StabilityParams {
  std::vector<std::string> methods{"m-sph"};
  std::map<std::string, MethodOptions> method_options;
  int dim = 2;
  CloudFamily cloud = CloudFamily::Uniform;
  Layout layout = Layout::Vertex;
  int n = 20;                 ///< intervals per direction of the unit box
  Real delta = 0.1001;        ///< perturbation (perturbed clouds)
  std::uint64_t seed = 1;
  Real support_factor = 2.4;  ///< support radius / dx
  KernelType kernel = KernelType::CubicSplineSPE;
  Real tau = 0.25;
  int k_samples = 16;         ///< wave vectors per direction
  bool keep_samples = false;  ///< keep every λ (for plots)
};

struct StabilityRow {
  std::string method;
  Index particles = 0, interior = 0;  ///< interior: support inside the domain
  Real max_abs = 0, max_abs_interior = 0, max_abs_boundary = 0, max_imag = 0, max_imag_interior = 0;
  Index unstable_interior = 0, unstable_boundary = 0;  ///< particles with some |λ| > 1 + 1e-12
  std::vector<std::complex<Real>> samples;            ///< with keep_samples (every particle's, thinned beyond 2e6)
  std::vector<char> sample_is_boundary;
};

struct StabilityResult {
  StabilityParams params;
  Real dx = 0, smoothing_length = 0;
  std::vector<StabilityRow> rows;
};

/// Throws ConfigError for bad parameters (tau <= 0, k_samples outside 1..256, ...).
StabilityResult run_stability(const StabilityParams& params);
Table to_table(const StabilityResult& result);

struct XiStatisticsRow {
  int neighbours = 0;
  Real mean = 0, std = 0, max = 0;
};
/// [SPE] Fig. 6: |ξ| over `configurations` random neighbour sets per count (seeded).
std::vector<XiStatisticsRow> xi_statistics(int dim, const std::vector<int>& neighbour_counts, int configurations,
                                           std::uint64_t seed);
Table to_table(const std::vector<XiStatisticsRow>& rows);

}  // namespace vrsph
