#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/core/resources.hpp>

namespace vrsph {

namespace {
std::once_flag default_once;
std::atomic<std::size_t> limit{0};
std::atomic<bool> limit_set{false};
}  // namespace

std::size_t available_memory_bytes() {
  std::ifstream f("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  std::string unit;
  while (f >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

std::size_t memory_limit_bytes() {
  std::call_once(default_once, [] {
    if (!limit_set.load()) limit.store(available_memory_bytes());
  });
  return limit.load();
}

void set_memory_limit_bytes(std::size_t bytes) {
  std::call_once(default_once, [] {});
  limit_set.store(true);
  limit.store(bytes);
}

std::size_t parse_memory_size(const std::string& text) {
  std::size_t split = text.size();
  while (split > 0 && std::isalpha(static_cast<unsigned char>(text[split - 1]))) --split;
  std::string unit = text.substr(split);
  for (auto& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const auto value = parse_real(text.substr(0, split));
  double scale = 0;
  if (unit.empty() || unit == "B") scale = 1;
  else if (unit == "K" || unit == "KB" || unit == "KIB") scale = 1024.0;
  else if (unit == "M" || unit == "MB" || unit == "MIB") scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "GB" || unit == "GIB") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "TB" || unit == "TIB") scale = 1024.0 * 1024 * 1024 * 1024;
  check<ConfigError>(value && scale > 0 && std::isfinite(*value) && *value >= 0 && *value * scale < 1e19,
                     "memory size '", printable(text), "' is not understood (examples: 8G, 512M, 0 for no limit)");
  return static_cast<std::size_t>(*value * scale);
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) {
    bytes /= 1024;
    ++u;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return buf;
}

std::size_t peak_resident_memory_bytes() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) {
      std::size_t kib = 0;
      std::istringstream(line.substr(6)) >> kib;
      return kib * 1024;
    }
  return 0;
}

void release_free_memory() {
#ifdef __GLIBC__
  ::malloc_trim(0);
#endif
}

bool reset_peak_resident_memory() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";  // resets the peak resident set size to the current one
  f.flush();
  return static_cast<bool>(f);
}

std::size_t resident_memory_bytes() {
  std::ifstream f("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  if (!(f >> size >> resident)) return 0;
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

void check_memory_estimate(double bytes, const std::string& what, const std::string& advice) {
  const std::size_t lim = memory_limit_bytes();
  if (lim == 0) return;
  // What the process already holds counts against the same limit.
  const auto in_use = static_cast<double>(resident_memory_bytes());
  if (bytes + in_use <= static_cast<double>(lim)) return;
  throw ResourceError(detail::concat(what, " needs about ", format_bytes(bytes), in_use > 0 ? " on top of the " : "",
                                     in_use > 0 ? format_bytes(in_use) + " in use" : std::string(),
                                     ", more than the memory limit of ", format_bytes(static_cast<double>(lim)),
                                     " (default: the memory available when the run started; --max-memory to "
                                     "change it); ", advice));
}

}  // namespace vrsph
