// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: the VTK XML (.vtu/.vtp) cloud reader — XML, base64, zlib blocks and
// appended data offsets all come from the input — and the neighbour search on a cloud it
// accepted. Only vrsph::Error may escape; anything else (a crash, a sanitizer report,
// another exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/io/vtk_cloud.hpp>
#include <vrsph/neighbours/search.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int dim = data[0] % 4;  // 0 = infer from the coordinates
  try {
    const vrsph::CloudFile f =
        vrsph::parse_vtk_cloud(std::string(reinterpret_cast<const char*>(data) + 1, size - 1), "fuzz.vtu", dim);
    vrsph::SearchParams sp;
    sp.radius = 2.5 * vrsph::estimate_spacing(f.cloud);
    sp.min_neighbours = 0;
    (void)vrsph::find_neighbours(f.cloud, sp);
  } catch (const vrsph::Error&) {
  }
  return 0;
}
