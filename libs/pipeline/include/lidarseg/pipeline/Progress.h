#pragma once
/// @file
/// lidarseg::pipeline: progress of a long run on stderr, shown only on a terminal.

#include <chrono>
#include <iomanip>
#include <iostream>
#include <string>

#include <unistd.h>

#include "lidarseg/pipeline/Timing.h"

namespace lidarseg::pipeline {

/// A counter with its rate (and, when the total is known, the share done and the time
/// left), redrawn at most 5 times a second.
class Progress {
 public:
  Progress(std::string tool, bool enabled, std::size_t total = 0)
      : tool_(std::move(tool)), enabled_(enabled && isatty(STDERR_FILENO) == 1), total_(total) {}
  void update(std::size_t done, bool force = false) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    const double rate = s > 0 ? static_cast<double>(done) / s : 0.0;
    std::cerr << "\r[" << tool_ << "] " << done;
    if (total_ > 0) std::cerr << "/" << total_;
    std::cerr << ", " << std::fixed << std::setprecision(1) << s << " s (" << std::setprecision(0) << rate << "/s";
    if (total_ > done && rate > 0) std::cerr << ", ~" << static_cast<double>(total_ - done) / rate << " s left";
    std::cerr << ")   " << std::defaultfloat << std::flush;
  }
  void done(std::size_t done) {
    if (!enabled_) return;
    update(done, true);
    std::cerr << "\n";
  }

 private:
  std::string tool_;
  bool enabled_;
  std::size_t total_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_{};
};

}  // namespace lidarseg::pipeline
