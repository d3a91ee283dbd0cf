#pragma once
/// @file FeaturesReport.h
/// What `lidarseg-features` measured over a log, and its report: features.md (tables of
/// recall and precision per type against a ground truth) and features.json.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/Feature.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/core/Statistics.h"
#include "lidarseg/core/WarningTally.h"
#include "lidarseg/eval/FeatureEvaluation.h"

namespace lidarseg::report {

/// Everything `lidarseg-features` measured.
struct FeaturesReport {
  std::string input;
  std::size_t scans = 0;
  std::size_t beams_per_scan = 0;
  std::array<std::size_t, kNumFeatureTypes> detections{};
  /// Time of FeatureDetector::detect() per scan (microseconds, wall clock).
  Summary detect_us;
  /// Time of segmentation (Wall-Danielsson + cascade) per scan (microseconds).
  Summary segment_us;
  /// Present when a ground truth was given.
  std::optional<eval::FeatureEvaluation> evaluation;
  Summary position_error_m;
  /// Camera images met, images given regions, regions in all, and the share of each
  /// image the regions cover (0..1, per image).
  std::size_t images = 0;
  std::size_t images_with_rois = 0;
  std::size_t rois = 0;
  Summary roi_coverage;
  /// Images skipped, then scans and lines skipped (the first 100, as report::RecordGate
  /// and the log reader keep them), each with where and why; and their count in all.
  std::vector<std::string> skipped;
  std::size_t skipped_count = 0;
  /// The stamps of the scans used, as lidarseg-odometry counts them (non-increasing, time
  /// gaps and clock jumps beyond [stamps] max_time_gap_s).
  StampCounts stamps;
  /// What the log reader and the stamp policy warned about, with its place in the log (the
  /// first 100): gaps, clock jumps, a laser whose layout changes, ...
  std::vector<std::string> log_warnings;
  /// The same warnings counted per kind in full (features.json's `warning_kinds`).
  WarningTally log_warning_kinds;
  /// What the run could not do but did not fail for, one line each (no figure without
  /// gnuplot, a --figure-scan beyond the log): printed by the tool after its results.
  std::vector<std::string> warnings;
};

/// features.md: counts and median times per scan, the regions of interest, and with a
/// ground truth the recall, precision, position error and confusion per type.
std::string featuresMarkdown(const FeaturesReport& report);

/// features.json: counts and median times, and the scores when a ground truth was given;
/// non-finite numbers as null.
std::string featuresJson(const FeaturesReport& report);

}  // namespace lidarseg::report
