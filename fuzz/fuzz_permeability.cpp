// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: the SPE10-style permeability reader (read_permeability) with the grid,
// subset and dimension taken from the input's first line ("I J K i0:i1 j0:j1 k0:k1 dim"), the
// rest being the file. Grid sizes near the 32-bit limit and files far too short for their
// grid are the classes the size corpus holds. Only vrsph::Error may escape.
#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/permeability.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = text.find('\n');
  if (eol == std::string::npos) return 0;
  std::istringstream head(text.substr(0, eol));
  vrsph::PermeabilityFileLayout layout;
  char colon = 0;
  head >> layout.grid[0] >> layout.grid[1] >> layout.grid[2];
  for (auto& range : layout.subset) head >> range[0] >> colon >> range[1];
  head >> layout.dim;
  if (!head) return 0;
  const std::string path =
      (std::filesystem::temp_directory_path() / ("vrsph-fuzz-perm-" + std::to_string(::getpid()) + ".dat")).string();
  {
    std::ofstream out(path, std::ios::binary);
    out << text.substr(eol + 1);
  }
  try {
    (void)vrsph::read_permeability(path, layout);
  } catch (const vrsph::Error&) {
  }
  std::filesystem::remove(path);
  return 0;
}
