// SPDX-License-Identifier: BSD-3-Clause
// Progress bars on a terminal (stderr): Progress, and EstimatedProgress ticking while one long call runs.
#include "cli_common.hpp"
#include <unistd.h>
#include <algorithm>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <thread>

namespace vrsph::cli {

Progress::Progress() : enabled_(::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (shown_) std::cerr << "\r\033[K" << std::flush;
}

void Progress::update(const std::string& label, double fraction) {
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed < 1.0 && !shown_) return;
  shown_ = true;
  const int width = 30, filled = static_cast<int>(fraction * width + 0.5);
  std::cerr << "\r[" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << static_cast<int>(100 * fraction)
            << "% " << label << " (" << static_cast<int>(elapsed) << " s)\033[K" << std::flush;
}

struct EstimatedProgress::State {
  std::mutex mutex;
  std::condition_variable stop_cv;
  bool stop = false;
  std::thread thread;
};

EstimatedProgress::EstimatedProgress(Progress& progress, std::string label, double from, double to,
                                     double estimated_seconds)
    : state_(std::make_unique<State>()) {
  const auto start = std::chrono::steady_clock::now();
  state_->thread = std::thread([this, &progress, label = std::move(label), from, to, estimated_seconds, start] {
    std::unique_lock lock(state_->mutex);
    while (!state_->stop_cv.wait_for(lock, std::chrono::milliseconds(250), [this] { return state_->stop; })) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress.update(label, from + (to - from) * std::min(0.99, t / std::max(estimated_seconds, 1e-3)));
    }
  });
}

EstimatedProgress::~EstimatedProgress() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->stop_cv.notify_all();
  state_->thread.join();
}

}  // namespace vrsph::cli
