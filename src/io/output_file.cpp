// SPDX-License-Identifier: BSD-3-Clause
#include <unistd.h>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vrsph/core/error.hpp>
#include <vrsph/io/output_file.hpp>

namespace vrsph {

namespace fs = std::filesystem;

namespace {
std::string reason() { return errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : std::string(); }

// Temporaries of writes in progress, in fixed storage a signal handler can read without
// allocating. A slot is claimed before the file is created and released after the rename.
constexpr std::size_t kSlots = 16, kPathBytes = 4096;
struct PendingSlot {
  std::atomic<bool> used{false};   // claimed by a writer
  std::atomic<bool> ready{false};  // path complete: the signal handler may remove it
  std::array<char, kPathBytes> path{};
};
std::array<PendingSlot, kSlots>& pending() {
  static std::array<PendingSlot, kSlots> slots;
  return slots;
}

// Holds one temporary path for the duration of a write: registered for the signal
// handler, removed on every exit path that did not rename it into place.
class PendingTemporary {
 public:
  explicit PendingTemporary(std::string path) : path_(std::move(path)) {
    if (path_.size() >= kPathBytes) return;  // not registered: only cleanup on signals is lost
    for (auto& s : pending()) {
      bool expected = false;
      if (s.used.load() || !s.used.compare_exchange_strong(expected, true)) continue;
      std::memcpy(s.path.data(), path_.c_str(), path_.size() + 1);
      s.ready.store(true);
      slot_ = &s;
      break;
    }
  }
  ~PendingTemporary() {
    if (!renamed_) ::unlink(path_.c_str());
    if (slot_) {
      slot_->ready.store(false);
      slot_->used.store(false);
    }
  }
  PendingTemporary(const PendingTemporary&) = delete;
  PendingTemporary& operator=(const PendingTemporary&) = delete;
  const std::string& path() const { return path_; }
  void renamed() { renamed_ = true; }

 private:
  std::string path_;
  PendingSlot* slot_ = nullptr;
  bool renamed_ = false;
};

// The file a write to `path` should replace: a symbolic link's target (so the link stays a
// link), else the path itself.
fs::path final_target(const std::string& path) {
  std::error_code ec;
  if (fs::is_symlink(path, ec)) {
    const fs::path t = fs::weakly_canonical(path, ec);
    if (!ec) return t;
  }
  return fs::path(path);
}

// Only regular files (or paths that do not exist yet) are replaced by a rename.
bool written_in_place(const fs::path& target) {
  std::error_code ec;
  const fs::file_status st = fs::status(target, ec);
  return fs::exists(st) && !fs::is_regular_file(st);
}

std::string temporary_beside(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // (concat: GCC 12 warns falsely, -Wstringop-overflow, on a chain of string operator+.)
  const std::string name = detail::concat(".", target.stem().string(), ".vrsph-", ::getpid(), "-", counter++, ".tmp",
                                          target.extension().string());
  return (dir / name).string();
}

void check_target(const std::string& path, const std::string& what) {
  check<IoError>(!path.empty(), "no file name given for the ", what);
  std::error_code ec;
  check<IoError>(!fs::is_directory(path, ec), "cannot write ", what, " '", path, "': it is a directory (give a file name)");
  // A rename would replace a file the user made read-only: refuse as writing it in place would.
  errno = 0;
  check<IoError>(!fs::exists(path, ec) || ::access(path.c_str(), W_OK) == 0, "cannot open ", what, " '", path,
                 "' for writing", reason());
}

void write_stream(const std::string& file, const std::string& shown, const std::string& what,
                  const std::function<void(std::ostream&)>& write) {
  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  check<IoError>(static_cast<bool>(out), "cannot open ", what, " '", shown, "' for writing", reason());
  write(out);
  errno = 0;
  out.flush();
  const bool flushed = static_cast<bool>(out);
  out.close();
  check<IoError>(flushed && !out.fail(), "error while writing ", what, " '", shown, "'", reason(),
                 ": the file is incomplete", shown == file ? "" : " (the previous file, if any, is unchanged)");
}

void rename_into_place(PendingTemporary& tmp, const fs::path& target, const std::string& shown, const std::string& what) {
  // A file replaced keeps its permissions (a temporary is created with the umask's).
  std::error_code ec;
  const fs::file_status old = fs::status(target, ec);
  if (!ec && fs::exists(old)) fs::permissions(tmp.path(), old.permissions(), ec);
  errno = 0;
  check<IoError>(std::rename(tmp.path().c_str(), target.c_str()) == 0, "cannot move the finished ", what, " into place at '",
                 shown, "'", reason());
  tmp.renamed();
}
}  // namespace

void write_file(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write) {
  check_target(path, what);
  const fs::path target = final_target(path);
  if (written_in_place(target)) return write_stream(path, path, what, write);
  PendingTemporary tmp(temporary_beside(target));
  write_stream(tmp.path(), path, what, write);
  rename_into_place(tmp, target, path, what);
}

void write_file_via(const std::string& path, const std::string& what,
                    const std::function<void(const std::string& temporary)>& produce) {
  check_target(path, what);
  const fs::path target = final_target(path);
  if (written_in_place(target)) return produce(path);
  PendingTemporary tmp(temporary_beside(target));
  produce(tmp.path());
  std::error_code ec;
  const auto size = fs::file_size(tmp.path(), ec);
  check<IoError>(!ec && size > 0, "the ", what, " '", path, "' was not written (its producer left no file)");
  rename_into_place(tmp, target, path, what);
}

void remove_pending_temporaries() noexcept {
  for (auto& s : pending())
    if (s.ready.load()) ::unlink(s.path.data());
}

void check_stream(std::ostream& out, const std::string& what) {
  errno = 0;
  out.flush();
  check<IoError>(static_cast<bool>(out), "error while writing ", what, reason(), ": the output is incomplete");
}

void check_output_is_not_input(const std::string& output, const std::string& input, const std::string& option) {
  if (output.empty() || input.empty()) return;
  std::error_code ec;
  const bool same = fs::equivalent(output, input, ec);
  check<ConfigError>(ec || !same, option, " '", output, "' is the input file '", input,
                     "': writing it would destroy the input; give another file name");
}

}  // namespace vrsph
