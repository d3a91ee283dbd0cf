#pragma once
/// @file SegmentationStats.h
/// The segmentation of a whole log summarised per cascade level (what `lidarseg-segment`
/// prints): segments per scan, their lengths, the share of the beams they hold, their fit
/// residuals and θ noise, and the time per scan of each stage (paper §II, Fig. 4).

#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/core/Statistics.h"
#include "lidarseg/core/WarningTally.h"

namespace lidarseg::eval {

/// Statistics of one cascade level over a whole log.
struct LevelStats {
  Summary segments_per_scan;
  Summary segment_length_m;
  /// Share of the valid beams that belong to a segment of this level (0..1).
  double point_coverage = 0.0;
  /// Mean RMS orthogonal residual of the segments (m).
  double mean_rms_residual_m = 0.0;
  /// Median standard deviation of theta from the noise model (rad), over the segments with
  /// a direction (0 when none has one).
  double median_theta_sigma_rad = 0.0;
  /// Segments whose points lie at one place (fitSegment()'s infinite covariance): no
  /// direction, left out of median_theta_sigma_rad.
  std::size_t segments_without_direction = 0;
};

/// Everything `lidarseg-segment` measured.
struct SegmentStatsReport {
  std::string input;
  std::string sensor_label;
  std::size_t scans = 0;
  /// Scans and lines that could not be processed, with where and why (the first 100),
  /// and their count in all.
  std::vector<std::string> skipped;
  std::size_t skipped_count = 0;
  /// The stamps of the scans used, as lidarseg-odometry counts them (non-increasing, time
  /// gaps and clock jumps beyond [stamps] max_time_gap_s).
  StampCounts stamps;
  /// What the log reader and the stamp policy warned about, with its place in the log (the
  /// first 100): gaps, clock jumps, a laser whose layout changes, ...
  std::vector<std::string> warnings;
  /// The same warnings counted per kind in full.
  WarningTally warning_kinds;
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

/// Accumulates the levels and stage times of every scan; summarise() fills a report.
/// O(segments) per scan; the samples are kept until the summary (medians).
class SegmentationStats {
 public:
  /// One scan's segmentation (every level) and its stage times (microseconds).
  void add(const Segmentation& seg, double wall_danielsson_us, double cascade_us);
  /// Fills the report's levels, valid beams, times and levels_never_gain_segments.
  void summarise(SegmentStatsReport& report) const;

 private:
  // One level's samples over the log.
  struct LevelAccumulator {
    std::vector<double> counts;
    std::vector<double> lengths;
    std::vector<double> theta_sigmas;
    double points = 0.0;
    double residual_sum = 0.0;
    std::size_t without_direction = 0;
  };
  std::array<LevelAccumulator, kNumCascadeLevels> acc_;
  std::vector<double> t_wd_, t_cascade_, t_total_, valid_beams_;
  double total_valid_ = 0.0;
  bool never_gain_ = true;
};

/// Writes the report as a readable table: the log and sensor, skipped scans, one row per
/// level (segments per scan, lengths in m, coverage in %, residuals in mm, σθ in degrees),
/// the stage times (µs) and whether a level ever gained segments.
void printSegmentStats(const SegmentStatsReport& report, std::ostream& os);

}  // namespace lidarseg::eval
