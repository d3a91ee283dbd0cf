#pragma once
/// @file
/// lidarseg::report: progress of a long run on stderr, shown only on a terminal.

#include <chrono>
#include <iomanip>
#include <iostream>
#include <string>

#include <unistd.h>

#include "lidarseg/report/Timing.h"

namespace lidarseg::report {

/// The time left of a run (s) after `elapsed_s` with `done` items done: from the rate of
/// the items when the `total` is known (> 0), else from the share of the input read
/// (`fraction`, 0 to 1: a log's bytes). Negative when neither tells (nothing done yet, no
/// total and no share, or the end already reached). O(1).
inline double secondsLeft(double elapsed_s, std::size_t done, std::size_t total, double fraction) {
  if (!(elapsed_s > 0)) return -1.0;
  if (total > 0) {
    return done > 0 && total > done ? elapsed_s / static_cast<double>(done) * static_cast<double>(total - done) : -1.0;
  }
  return fraction > 0 && fraction < 1 ? elapsed_s * (1.0 - fraction) / fraction : -1.0;
}

/// A counter with its rate and the time left (secondsLeft(): from the total when known,
/// else from the share of the input read), on stderr, redrawn at most 5 times a second;
/// shown only when stderr is a terminal.
class Progress {
 public:
  /// `total`: the items the run will count (0: not known).
  Progress(std::string tool, bool enabled, std::size_t total = 0)
      : tool_(std::move(tool)), enabled_(enabled && isatty(STDERR_FILENO) == 1), total_(total) {}
  /// `done` items so far; `fraction`: the share of the input read (0 to 1), for the time
  /// left when the total is not known (a negative value: not known either).
  void update(std::size_t done, double fraction = -1.0, bool force = false) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    const double rate = s > 0 ? static_cast<double>(done) / s : 0.0;
    std::cerr << "\r[" << tool_ << "] " << done;
    if (total_ > 0) std::cerr << "/" << total_;
    std::cerr << ", " << std::fixed << std::setprecision(1) << s << " s (" << std::setprecision(rate < 10 ? 1 : 0)
              << rate << "/s";
    if (total_ == 0 && fraction > 0) std::cerr << ", " << std::setprecision(0) << 100.0 * fraction << " % read";
    const double left = secondsLeft(s, done, total_, fraction);
    if (left >= 0) std::cerr << ", ~" << std::setprecision(0) << left << " s left";
    std::cerr << ")   " << std::defaultfloat << std::flush;
  }
  /// The last line, then a line break.
  void done(std::size_t done) {
    if (!enabled_) return;
    update(done, -1.0, true);
    std::cerr << "\n";
  }

 private:
  std::string tool_;
  bool enabled_;
  std::size_t total_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_{};
};

}  // namespace lidarseg::report
