#pragma once
/// @file
/// lidarseg::report: wall-clock timing of the per-scan steps the apps report.

#include <chrono>

namespace lidarseg::report {

using Clock = std::chrono::steady_clock;

/// Microseconds elapsed since t0.
inline double microsecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

}  // namespace lidarseg::report
