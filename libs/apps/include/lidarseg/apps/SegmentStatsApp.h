#pragma once
/// @file SegmentStatsApp.h
/// The logic of `lidarseg-segment`: segment every scan of a log and summarise each level.

#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/Statistics.h"

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

/// Statistics of one cascade level over a whole log.
struct LevelStats {
  Summary segments_per_scan;
  Summary segment_length_m;
  /// Share of the valid beams that belong to a segment of this level (0..1).
  double point_coverage = 0.0;
  /// Mean RMS orthogonal residual of the segments (m).
  double mean_rms_residual_m = 0.0;
  /// Median standard deviation of theta from the noise model (rad).
  double median_theta_sigma_rad = 0.0;
};

/// Everything `lidarseg-segment` measured.
struct SegmentStatsReport {
  std::string input;
  std::string sensor_label;
  std::size_t scans = 0;
  /// Scans that could not be processed, with the reason (scan index and message).
  std::vector<std::string> skipped;
  std::size_t beams_per_scan = 0;
  double field_of_view_deg = 0.0;
  double max_range_m = 0.0;
  Summary valid_beams_per_scan;
  std::array<LevelStats, kNumCascadeLevels> levels;
  /// Per-scan wall-clock times (microseconds).
  Summary wall_danielsson_us;
  Summary cascade_us;
  Summary total_us;
  /// Whether every level had no more segments than the previous one on every scan.
  bool levels_never_gain_segments = true;
};

/// Segments every scan of a laser log at all cascade levels and summarises the result.
class SegmentStatsApp {
 public:
  explicit SegmentStatsApp(SegmentStatsOptions options);

  /// Processes the whole input.
  /// @throws std::runtime_error / std::invalid_argument for an unreadable input or config
  /// (naming the file and entry or key). A scan that cannot be segmented is skipped and
  /// listed in the report instead.
  SegmentStatsReport run();

  /// Writes the report as a readable table.
  static void print(const SegmentStatsReport& report, std::ostream& os);
  /// The run's warnings on `err` (stderr), after the results: the skipped scans counted,
  /// with the first in full. Nothing when none was skipped.
  static void printWarnings(const SegmentStatsReport& report, std::ostream& err);

 private:
  SegmentStatsOptions options_;
};

}  // namespace lidarseg::apps
