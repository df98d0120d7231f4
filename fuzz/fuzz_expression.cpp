// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: user expressions (--u, --a, --f, --g, --q). The text is parsed
// as a muParser expression and as a catalogue-or-expression function, then evaluated
// with its finite-difference gradient and Laplacian at a few points. Only
// vrsph::Error may escape.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int dim = 1 + data[0] % 3;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const vrsph::Vec3 points[] = {vrsph::Vec3(0.25, 0.5, 0.75), vrsph::Vec3(0, 0, 0), vrsph::Vec3(-1, 2, 1e3)};
  try {
    const vrsph::Expression e(text);
    for (const auto& x : points) (void)e(x);
  } catch (const vrsph::Error&) {
  }
  try {
    const auto f = vrsph::make_function_or_expression(text, dim);
    for (const auto& x : points) {
      (void)f->value(x);
      (void)f->gradient(x);
      (void)f->laplacian(x);
    }
  } catch (const vrsph::Error&) {
  }
  return 0;
}
