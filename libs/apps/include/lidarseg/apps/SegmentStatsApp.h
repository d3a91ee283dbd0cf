#pragma once
/// @file SegmentStatsApp.h
/// The logic of `lidarseg-segment`: segment every scan of a log and summarise each level.

#include <cstddef>
#include <iosfwd>
#include <string>

#include "lidarseg/eval/SegmentationStats.h"

namespace lidarseg::apps {

/// Command-line options of `lidarseg-segment`.
struct SegmentStatsOptions {
  /// MRPT .rawlog or CARMEN log (.clf/.log, optionally .gz) to read.
  std::string input;
  /// Optional INI or YAML file with a [segmentation] section; defaults otherwise.
  std::string config_path;
  std::string section = "segmentation";
  /// Laser to use when the log has several; empty = the first one seen.
  std::string sensor_label;
  /// Stop after this many scans (0 = all).
  std::size_t max_scans = 0;
  /// Optional per-scan CSV output (written atomically).
  std::string csv_path;
  /// Progress with rate and ETA on stderr (shown only when stderr is a terminal; -q: off).
  bool progress = true;
};

/// Everything `lidarseg-segment` measured (lidarseg::eval's, with its printer).
using SegmentStatsReport = eval::SegmentStatsReport;

/// Segments every scan of a laser log at all cascade levels and summarises the result.
class SegmentStatsApp {
 public:
  explicit SegmentStatsApp(SegmentStatsOptions options);

  /// Processes the whole input.
  /// @throws std::runtime_error / std::invalid_argument for an unreadable input or config
  /// (naming the file and entry or key). A scan that cannot be segmented is skipped and
  /// listed in the report instead.
  SegmentStatsReport run();

  /// Writes the report as a readable table (eval::printSegmentStats), then the log's counts
  /// as lidarseg-odometry prints them ("skipped: N, non-increasing stamps: N, time gaps: N,
  /// clock jumps: N").
  static void print(const SegmentStatsReport& report, std::ostream& os);
  /// The run's warnings on `err` (stderr), after the results, as lidarseg-odometry prints
  /// them: one line per kind of the log's warnings (time gaps, clock jumps, ...) with its
  /// count and first place, then the skipped scans counted with the first in full. Nothing
  /// when there is none.
  static void printWarnings(const SegmentStatsReport& report, std::ostream& err);

 private:
  SegmentStatsOptions options_;
};

}  // namespace lidarseg::apps
