// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: the Gmsh mesh reader (MSH 4.1 and 2.2 sections, element tables, boundary
// detection and normals). Only vrsph::Error may escape; anything else (a crash, a sanitizer
// report, another exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/io/gmsh_cloud.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)vrsph::parse_gmsh_cloud(std::string(reinterpret_cast<const char*>(data), size), "fuzz.msh");
  } catch (const vrsph::Error&) {
  }
  return 0;
}
