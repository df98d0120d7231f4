// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// [AAR] §5 vibration test (METHODS §5.2): x'' + ω² x = 0 on
// [0,1], x(0) = x(1) = 0, exact ω_n = nπ. K is a method's second-derivative stencil on
// the n - 1 interior particles of n + 1 equispaced particles (ends fixed and eliminated,
// unit density: identity mass); the eigenvalues λ of -K approximate ω². Reported: the
// normalised spectrum ω_n^h / ω_n = sqrt(λ_n) / (nπ), eigenvalues sorted by real part,
// beside the lumped-mass linear FEM reference (its matrix is assembled and solved by the
// same eigensolver; closed form sin(nπ dx/2)/(nπ dx/2)).
// The matrices are non-symmetric: complex eigenvalues are reported through max_imag.
#include <string>
#include <vector>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/options.hpp>

namespace vrsph {

struct SpectrumParams {
  std::string method = "fpm2o";
  MethodOptions options;
  int n = 101;  ///< intervals: n + 1 particles, n - 1 unknowns ([AAR]: 101 -> 100 unknowns)
  KernelType kernel = KernelType::Gaussian;
  Real h_factor = 6;  ///< support radius / dx (Gaussian l = dx)
  CloudFamily cloud = CloudFamily::Uniform;
  Real delta = 0.25;
  std::uint64_t seed = 1;
};

struct Spectrum {
  std::vector<Real> omega_ratio;  ///< sqrt(Re λ_n)/(nπ), NaN where Re λ_n < 0
  Real max_imag_relative = 0;     ///< max |Im λ| / |λ|
  Index negative = 0;             ///< eigenvalues with Re λ < 0 (unstable modes)
};

/// Throws ConfigError (method without a Laplacian, n < 3) or NumericalError (eigensolver
/// did not converge).
Spectrum vibration_spectrum(const SpectrumParams& params);
/// Memory (bytes) and time (seconds, one core) of one dense eigenvalue problem with n
/// intervals, estimated before it starts: O(n^2) and O(n^3). vibration_spectrum refuses
/// a problem above the memory limit (ResourceError); the CLI prints the time estimate.
double dense_spectrum_bytes(int n);
double dense_spectrum_seconds(int n);
/// The seconds of vibration_spectrum(params) predicted at run time: the same problem at a
/// quarter of the intervals (at least 3, a sixty-fourth of the work) is solved and timed,
/// and its time scaled by the cube of the unknowns. The static estimate above assumes a
/// fixed rate and was 2.5x low on a loaded machine; this one sees the machine as it is now.
double calibrated_spectrum_seconds(const SpectrumParams& params);
/// Calibration of dense_spectrum_seconds (measured on the 2-core CI machine).
inline constexpr double dense_spectrum_flops_per_second = 8e9;
/// Throws ConfigError for n outside 3..5000 and ResourceError above the memory limit.
void check_spectrum_size(int n);

/// Lumped-mass linear FEM on the same particles: eigenvalues of tridiag(-1, 2, -1)/dx².
Spectrum fem_lumped_spectrum(int n);
/// The same in closed form, sin(kπ dx/2)/(kπ dx/2), k = 1..n-1.
std::vector<Real> fem_lumped_closed_form(int n);

}  // namespace vrsph
