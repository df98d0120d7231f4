#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>

namespace vrsph {

namespace {
std::string reason() { return errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : std::string(); }
}  // namespace

void write_file(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write) {
  check<IoError>(!path.empty(), "no file name given for the ", what);
  std::error_code ec;
  check<IoError>(!std::filesystem::is_directory(path, ec), "cannot write ", what, " '", path,
                 "': it is a directory (give a file name)");
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  check<IoError>(static_cast<bool>(out), "cannot open ", what, " '", path, "' for writing", reason());
  write(out);
  errno = 0;
  out.flush();
  const bool flushed = static_cast<bool>(out);
  out.close();
  check<IoError>(flushed && !out.fail(), "error while writing ", what, " '", path, "'", reason(),
                 ": the file is incomplete");
}

void check_stream(std::ostream& out, const std::string& what) {
  errno = 0;
  out.flush();
  check<IoError>(static_cast<bool>(out), "error while writing ", what, reason(), ": the output is incomplete");
}

}  // namespace vrsph
