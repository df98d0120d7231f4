// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Memory budget. Large allocations (neighbour lists, stencils, dense matrices) are
// estimated from the problem size *before* they are made and checked against one
// process-wide limit, so an oversized run is refused at once with the estimate and
// the limit (ResourceError) instead of failing with std::bad_alloc after minutes,
// or being killed by the kernel, with the machine swapping in between.
#include <cstddef>
#include <string>

namespace vrsph {

/// Memory the system can still give this process, in bytes: MemAvailable of /proc/meminfo,
/// or less where the process's cgroup (v2 memory.max, v1 limit_in_bytes) leaves less; 0 if
/// unknown. Under ulimit -v, check_memory_estimate also refuses what would not fit in the
/// address space left.
std::size_t available_memory_bytes();

/// The process-wide limit in bytes for what a run allocates; 0 = no limit. Default:
/// available_memory_bytes() at the first call (so a run never plans to use more than the
/// machine has free). What the process held when the limit was fixed (an interpreter, its
/// libraries) does not count against it; what the run has allocated since does.
std::size_t memory_limit_bytes();
void set_memory_limit_bytes(std::size_t bytes);

/// "8G", "512M", "1.5GiB", "100000" (bytes), "0" (no limit) -> bytes. Throws
/// ConfigError on anything else.
std::size_t parse_memory_size(const std::string& text);
/// 1536 MiB -> "1.5 GiB".
std::string format_bytes(double bytes);

/// Resident memory of this process now (VmRSS), in bytes; 0 if unknown.
std::size_t resident_memory_bytes();
/// Peak resident memory of this process so far (VmHWM), in bytes; 0 if unknown.
std::size_t peak_resident_memory_bytes();
/// Starts a new peak: peak_resident_memory_bytes() then measures from now (Linux
/// /proc/self/clear_refs); false where that is not possible (the peak stays global).
bool reset_peak_resident_memory();
/// Returns freed heap memory to the system (glibc malloc_trim), so that the resident
/// size measures what is in use; for memory measurements between runs.
void release_free_memory();

/// Throws ResourceError if `bytes` (an estimate for `what`) plus the memory the run already
/// holds exceeds the limit, or if `bytes` exceeds the address space left under ulimit -v;
/// the message gives the numbers and `advice`.
void check_memory_estimate(double bytes, const std::string& what, const std::string& advice);

}  // namespace vrsph
