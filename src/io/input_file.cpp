#include <filesystem>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/input_file.hpp>

namespace vrsph {

std::ifstream open_input(const std::string& path, const std::string& what) {
  std::error_code ec;
  check<IoError>(!std::filesystem::is_directory(path, ec), what, " '", path, "' is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  check<IoError>(static_cast<bool>(in), "cannot open ", what, " '", path, "'",
                 std::filesystem::exists(path, ec) ? " (permission denied?)" : " (no such file)");
  return in;
}

std::string read_file(const std::string& path, const std::string& what) {
  std::ifstream in = open_input(path, what);
  std::ostringstream text;
  text << in.rdbuf();
  check<IoError>(!in.bad(), "cannot read ", what, " '", path, "'");
  return text.str();
}

}  // namespace vrsph
