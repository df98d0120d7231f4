// SPDX-License-Identifier: BSD-3-Clause
#include <filesystem>
#include <limits>
#include <vector>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/io/input_file.hpp>

namespace vrsph {

std::ifstream open_input(const std::string& path, const std::string& what) {
  std::error_code ec;
  check<IoError>(!std::filesystem::is_directory(path, ec), what, " '", path, "' is a directory, not a file");
  // A device (/dev/zero, a terminal) never ends or blocks: reading it would fill memory or hang.
  check<IoError>(!std::filesystem::is_character_file(path, ec) && !std::filesystem::is_block_file(path, ec), what, " '",
                 path, "' is a device, not a file");
  std::ifstream in(path, std::ios::binary);
  check<IoError>(static_cast<bool>(in), "cannot open ", what, " '", path, "'",
                 std::filesystem::exists(path, ec) ? " (permission denied?)" : " (no such file)");
  return in;
}

std::string read_file(const std::string& path, const std::string& what) {
  std::ifstream in = open_input(path, what);
  // In chunks, up to a quarter of the memory vrsph may use (a pipe has no size to check first;
  // what is parsed from the text needs memory too).
  const std::size_t cap = memory_limit_bytes();  // 0: no limit
  const std::size_t limit = cap > 0 ? cap / 4 : std::numeric_limits<std::size_t>::max();
  std::string text;
  std::vector<char> chunk(std::size_t{1} << 20);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > limit)
      throw ResourceError(detail::concat(what, " '", path, "' is larger than ", format_bytes(static_cast<double>(limit)),
                                         " (a quarter of the memory limit): too large to read"));
  }
  check<IoError>(!in.bad(), "cannot read ", what, " '", path, "'");
  return text;
}

}  // namespace vrsph
