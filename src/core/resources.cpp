// SPDX-License-Identifier: BSD-3-Clause
#include <sys/resource.h>
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
// Resident memory when the limit was fixed: what the process held before the run (an
// interpreter, shared libraries) is not the run's and does not count against its budget.
std::atomic<std::size_t> baseline{0};

std::size_t meminfo_available() {
  std::ifstream f("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  std::string unit;
  while (f >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

// A number of bytes from a cgroup file; 0 for "max", a missing file or anything unreadable.
std::size_t cgroup_value(const std::string& path) {
  std::ifstream f(path);
  std::string text;
  if (!(f >> text)) return 0;
  const auto v = parse_integer(text);
  return v && *v > 0 && *v < (1ll << 62) ? static_cast<std::size_t>(*v) : 0;
}

// The memory this process's cgroup may still take (cgroup v2 memory.max - memory.current, or
// v1's limit_in_bytes - usage_in_bytes); 0 when no cgroup limits it.
std::size_t cgroup_headroom() {
  std::ifstream self("/proc/self/cgroup");
  std::string line, v2_path;
  while (std::getline(self, line))
    if (line.rfind("0::", 0) == 0) v2_path = line.substr(3);
  for (const std::string& dir : {std::string("/sys/fs/cgroup") + v2_path, std::string("/sys/fs/cgroup")}) {
    const std::size_t max = cgroup_value(dir + "/memory.max");
    if (max > 0) {
      const std::size_t current = cgroup_value(dir + "/memory.current");
      return max > current ? max - current : 1;
    }
  }
  const std::size_t v1 = cgroup_value("/sys/fs/cgroup/memory/memory.limit_in_bytes");
  if (v1 > 0 && v1 < (std::size_t{1} << 60)) {  // v1 writes a huge number for "no limit"
    const std::size_t used = cgroup_value("/sys/fs/cgroup/memory/memory.usage_in_bytes");
    return v1 > used ? v1 - used : 1;
  }
  return 0;
}

// This process's mapped (VmSize) and resident (VmRSS) bytes from /proc/self/statm; 0 if unknown.
struct Statm {
  std::size_t mapped = 0, resident = 0;
};
Statm statm() {
  std::ifstream f("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  if (!(f >> size >> resident)) return {};
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  return {size * page, resident * page};
}

// The address space this process may still map under RLIMIT_AS (ulimit -v); 0 = unlimited.
std::size_t address_space_headroom() {
  rlimit rl{};
  if (::getrlimit(RLIMIT_AS, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return 0;
  const std::size_t mapped = statm().mapped;
  return rl.rlim_cur > mapped ? static_cast<std::size_t>(rl.rlim_cur) - mapped : 1;
}

std::size_t smallest_nonzero(std::initializer_list<std::size_t> values) {
  std::size_t best = 0;
  for (const std::size_t v : values)
    if (v > 0 && (best == 0 || v < best)) best = v;
  return best;
}
}  // namespace

std::size_t available_memory_bytes() { return smallest_nonzero({meminfo_available(), cgroup_headroom()}); }

std::size_t memory_limit_bytes() {
  std::call_once(default_once, [] {
    if (!limit_set.load()) {
      limit.store(available_memory_bytes());
      baseline.store(resident_memory_bytes());
    }
  });
  return limit.load();
}

void set_memory_limit_bytes(std::size_t bytes) {
  std::call_once(default_once, [] {});
  limit_set.store(true);
  limit.store(bytes);
  baseline.store(resident_memory_bytes());
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

std::size_t resident_memory_bytes() { return statm().resident; }

void check_memory_estimate(double bytes, const std::string& what, const std::string& advice) {
  // The address space left under ulimit -v binds whatever the budget says: allocations
  // beyond it fail however much memory the machine has.
  // The address space a run maps exceeds what it holds resident (allocator arenas, thread
  // stacks, fragmentation): measured under ulimit -v 2G, a study whose estimate was 0.89 of the
  // room left ran out in std::bad_alloc and one at 0.80 completed; 0.85 separates them.
  const double usable = 0.85 * static_cast<double>(address_space_headroom());
  if (usable > 0 && bytes > usable)
    throw ResourceError(detail::concat(what, " needs about ", format_bytes(bytes), ", more than the ", format_bytes(usable),
                                       " of address space this process may still use (85 % of what its limit, ulimit "
                                       "-v, leaves); ",
                                       advice));
  const std::size_t lim = memory_limit_bytes();
  if (lim == 0) return;
  // What the run already holds counts against its budget; what the process held before the
  // run (the baseline) does not.
  const std::size_t now = resident_memory_bytes(), before = baseline.load();
  const auto in_use = static_cast<double>(now > before ? now - before : 0);
  if (bytes + in_use <= static_cast<double>(lim)) return;
  throw ResourceError(detail::concat(what, " needs about ", format_bytes(bytes), in_use > 0 ? " on top of the " : "",
                                     in_use > 0 ? format_bytes(in_use) + " this run holds" : std::string(),
                                     ", more than the memory limit of ", format_bytes(static_cast<double>(lim)),
                                     " (default: the memory available when the run started, within this process's "
                                     "cgroup limit; --max-memory to change it); ", advice));
}

}  // namespace vrsph
