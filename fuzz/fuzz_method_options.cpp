// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: --method-opt items (one key=value per line) given to every
// registered method, which parses and validates them in its constructor. Only
// vrsph::Error may escape.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/methods/registry.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<std::string> items;
  for (std::string line; std::getline(in, line);) items.push_back(line);
  try {
    const vrsph::MethodOptions options = vrsph::MethodOptions::parse(items);
    for (const auto& info : vrsph::builtin_methods().list()) {
      try {
        (void)vrsph::builtin_methods().create(info.name, options);
      } catch (const vrsph::Error&) {
      }
    }
  } catch (const vrsph::Error&) {
  }
  return 0;
}
