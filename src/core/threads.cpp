// SPDX-License-Identifier: BSD-3-Clause
#include <cctype>
#include <cstdlib>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/threads.hpp>

namespace vrsph {

namespace {
// OMP_STACKSIZE as the OpenMP standard writes it: a positive integer with an optional
// B, K, M or G suffix (K when none), blanks around either part allowed.
double stack_size_bytes(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  const std::size_t digits = i;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
  if (i == digits || i - digits > 15) return -1;
  const double value = std::strtod(text.substr(digits, i - digits).c_str(), nullptr);
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  double scale = 1024;
  if (i < text.size()) {
    switch (std::toupper(static_cast<unsigned char>(text[i]))) {
      case 'B': scale = 1; break;
      case 'K': scale = 1024; break;
      case 'M': scale = 1024.0 * 1024; break;
      case 'G': scale = 1024.0 * 1024 * 1024; break;
      default: return -1;
    }
    ++i;
  }
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  return i == text.size() ? value * scale : -1;
}
}  // namespace

std::string sanitise_openmp_environment() {
  if (const char* stack = std::getenv("OMP_STACKSIZE")) {
    const double bytes = stack_size_bytes(stack);
    check<ConfigError>(bytes > 0 && bytes <= 1024.0 * 1024 * 1024, "OMP_STACKSIZE='", printable(stack),
                       "' is not a usable thread stack size (a positive number with an optional B, K, M or G suffix, "
                       "at most 1G; unset it to use the default)");
  }
#ifdef _OPENMP
  const char* wanted = std::getenv("OMP_NUM_THREADS");
  const int cores = omp_get_num_procs();
  if (wanted && omp_get_max_threads() > cores) {
    omp_set_num_threads(cores);
    return detail::concat("OMP_NUM_THREADS=", printable(wanted), " asks for more threads than the ", cores,
                          " cores of this machine; using ", cores);
  }
#endif
  return "";
}

}  // namespace vrsph
