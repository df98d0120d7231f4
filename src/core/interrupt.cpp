// SPDX-License-Identifier: BSD-3-Clause
#include <atomic>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <vrsph/core/error.hpp>
#include <vrsph/core/interrupt.hpp>

namespace vrsph {

namespace {
std::atomic<InterruptCheck> the_check{nullptr};
std::atomic<bool> requested{false};

bool on_calling_thread() {
#ifdef _OPENMP
  return omp_get_thread_num() == 0;
#else
  return true;
#endif
}

void poll() {
  const InterruptCheck check = the_check.load(std::memory_order_relaxed);
  if (check && on_calling_thread() && check()) requested.store(true);
}
}  // namespace

void set_interrupt_check(InterruptCheck check) { the_check.store(check); }

void check_interrupt() {
  poll();
  if (requested.exchange(false)) throw Interrupted("interrupted");
}

bool interrupt_pending(long long iteration, long long every) {
  if (the_check.load(std::memory_order_relaxed) == nullptr) return false;
  if (every > 0 && iteration % every == 0) poll();
  return requested.load(std::memory_order_relaxed);
}

}  // namespace vrsph
