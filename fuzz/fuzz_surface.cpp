// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: closed surfaces (our STL ASCII/binary, OFF and OBJ readers, then CGAL's
// soup repair, orientation and mesh building; the first byte picks the format), the closedness / self-intersection / orientation checks,
// and, for small surfaces, the fill and the boundary sample. Only vrsph::Error may escape;
// anything else (a crash, a sanitizer report, another exception, a hang) is a finding.
#include <unistd.h>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/core/error.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const ext[] = {".off", ".stl", ".obj"};
  // CGAL reads files: one scratch file per process.
  const auto path = (std::filesystem::temp_directory_path() /
                     ("vrsph_fuzz_surface_" + std::to_string(::getpid()) + ext[data[0] % 3]))
                        .string();
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  try {
    const vrsph::ClosedSurface s = vrsph::read_closed_surface(path);
    vrsph::GeometryFill fill;
    fill.spacing = (s.hi() - s.lo()).minCoeff() / 4;
    fill.pattern = data[0] & 4 ? vrsph::FillPattern::BlueNoise : vrsph::FillPattern::Lattice;
    // Bounded work per input: at most ~1e5 surface candidates and a small triangle count.
    if (s.triangles() <= 200 && fill.spacing > 0 && s.area() / (fill.spacing * fill.spacing) < 3000) {
      (void)vrsph::fill_surface(s, fill);
      (void)s.sample(fill.spacing);
    }
  } catch (const vrsph::Error&) {
  }
  std::filesystem::remove(path);
  return 0;
}
