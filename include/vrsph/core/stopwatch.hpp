// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Wall-clock seconds for per-stage timings in studies and benchmarks.
#include <chrono>

namespace vrsph {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace vrsph
