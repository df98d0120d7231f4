// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The operator tests of [SPE] §4 (METHODS §5.3 "Operator
// tests"): a scheme's div(m grad u) evaluated at every particle of a patch and reported
// along a cross-section, as in the paper's figures.
//   r2             Figs. 1–2: ∇²(x² + y²) = 4 on [-1/2, 1/2]², dx = 0.1 (11 × 11), f = 1.0,
//                  cross-section y = 0.
//   power-sum      Fig. 3 and (79a): u_s = Σ_k x_k^s on |x_k - 2.5| <= 1/2, 21 particles per
//                  direction (dx = 0.05), f = 1.2, cross-section y = 2.5 (s = 3: ∇²(x³ + y³)).
//   product        (79b) with m_k = s: u = Π_k x_k^s ((xy)^s in 2D), same patch.
//   heterogeneous  Fig. 4 and (80): ∇·(m ∇u) with m = Σ_k x_k and u = u_s (s = 1:
//                  ∇·((x + y)∇(x + y)) = 2), same patch.
// rotated: the lattice turned by 45° about the patch centre and clipped to the patch (the
// paper's test of off-diagonal terms). Every particle gets an operator row (no ghosts: the
// supports of the outer particles are truncated, as in the paper). Errors: pointwise along
// the cross-section, the RMS error (78) over all particles (an absolute error, METHODS R20),
// and the largest error over "deep" particles whose whole support lies inside the patch.
#include <string>
#include <vector>
#include <vrsph/io/table.hpp>
#include <vrsph/methods/options.hpp>

namespace vrsph {

struct SpePatchVariant {
  std::string method;      ///< registry name, e.g. "m-sph"
  MethodOptions options;   ///< e.g. gradient=g2
  std::string label;       ///< "m-sph g2" (method and the option values)
};

/// "m-sph" or "m-sph:gradient=g2,pair_gradient=corrected" -> a variant with its label.
SpePatchVariant parse_patch_variant(const std::string& spec);

struct SpePatchParams {
  std::string test = "power-sum";  ///< r2 | power-sum | product | heterogeneous
  int exponent = 3;                ///< s (power-sum, product, heterogeneous)
  int dim = 2;
  bool rotated = false;
  Real f = 0;                      ///< smoothing length / dx (0: the test's default, 1.0 for r2, else 1.2)
  Real delta = 0;                  ///< perturbation U(-delta dx, delta dx) of the particles (0: lattice)
  std::uint64_t seed = 1;
  std::vector<SpePatchVariant> variants;
};

struct SpePatchSummary {
  std::string label;
  Real rms = 0;            ///< (78) over all particles
  Real max_deep = 0;       ///< max |error| over particles whose support lies inside the patch
  Real max_boundary = 0;   ///< max |error| over the other particles
  Real boundary_on_line = 0;  ///< |error| at the first particle of the cross-section (x = left side)
};

struct SpePatchResult {
  SpePatchParams params;
  std::vector<Real> x;                 ///< coordinate along the cross-section
  std::vector<Real> exact;             ///< exact operator value there
  std::vector<std::vector<Real>> value;  ///< per variant, along the cross-section
  std::vector<SpePatchSummary> summary;
  Index particles = 0;
  Real dx = 0, support = 0;
};

/// Throws ConfigError (unknown test, exponent outside 1..8, dimension, variants without a
/// div-a-grad operator) before any work.
SpePatchResult run_spe_patch(const SpePatchParams& params);
/// Long format for plots and files: one row per (variant, particle on the cross-section).
Table profile_table(const SpePatchResult& r);
/// One row per variant: rms, max_deep, max_boundary, boundary_on_line.
Table summary_table(const SpePatchResult& r);

}  // namespace vrsph
