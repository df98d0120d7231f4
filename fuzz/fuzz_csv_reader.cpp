// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: the CSV point-cloud reader, and what a user does next with a
// cloud it accepted (spacing estimate, neighbour search). Only vrsph::Error may
// escape the library; anything else (a crash, a sanitizer report, another exception,
// a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/neighbours/search.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int dim = data[0] % 4;  // 0 = infer from the columns
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    const vrsph::PointCloud cloud = vrsph::read_csv_with_fields(in, "fuzz.csv", dim).cloud;
    const vrsph::Real spacing = vrsph::estimate_spacing(cloud);
    vrsph::SearchParams sp;
    sp.radius = 2.5 * spacing;
    sp.min_neighbours = 0;
    (void)vrsph::find_neighbours(cloud, sp);
  } catch (const vrsph::Error&) {
  }
  return 0;
}
