#pragma once
/// @file RunReport.h
/// What an odometry run measured: per method, its trajectory, times, statuses and errors;
/// for the run, what the log and the stamp policy made of the input. One value, written
/// by every tool through the same writers (TUM, timing CSV, summary JSON, Markdown).

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Statistics.h"
#include "lidarseg/eval/Relations.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/eval/TrajectoryMetrics.h"
#include "lidarseg/report/RecordGate.h"

namespace lidarseg::report {

/// Figures of one method over a run.
struct MethodReport {
  std::string name;
  eval::StampedTrajectory trajectory;
  /// Time per scan (microseconds); for lidarseg also the stages.
  std::vector<double> time_us;
  Summary time_summary_us;
  std::vector<double> segmentation_us, cascade_us, matching_us;
  /// lidarseg, per scan: refinement (and search) time (part of matching_us), the
  /// refinement's inlier ratio and iterations, and the segment match's status.
  std::vector<double> refinement_us, inlier_ratio;
  std::vector<std::size_t> refine_iterations;
  std::vector<std::string> match_status;
  /// lidarseg, per scan: the predicted motion since the previous scan (sensor frame).
  std::vector<Pose2D> prior;
  /// Per scan: the match status ("first" for the first scan) and the number of couples.
  std::vector<std::string> scan_status;
  std::vector<std::size_t> scan_matches;
  /// lidarseg: scans per tracking status ("ok", "degenerate", "recovered", "lost"); ICP:
  /// "converged", "not_converged", "skipped".
  std::map<std::string, std::size_t> status_counts;
  /// lidarseg: why the segment match failed (too few couples), by its dominant rejection
  /// ("gated", "over_threshold", "ambiguous", "not_mutual", "outliers", "none"), whatever the
  /// refinement or the search made of the scan afterwards.
  std::map<std::string, std::size_t> match_failures;
  /// lidarseg, per scan: whether the correlative search ran (the recovery of a doubtful or
  /// failed refinement), and how many scans it ran on.
  std::vector<char> searched;
  std::size_t searches = 0;
  /// lidarseg: how many scans also ran the wider second search (the segment match, the
  /// first search and every refinement failed; decision 83).
  std::size_t wide_searches = 0;
  /// lidarseg: how many scans were segmented again with the rotation rate their refinement
  /// measured (decision 90).
  std::size_t deskewed_again = 0;
  /// lidarseg: how many keyframes were revised at the next scan with the rotation rate
  /// measured over their sweep (decision 114).
  std::size_t revised_keyframes = 0;
  /// lidarseg: the index of every lost scan (the first 1000).
  std::vector<std::size_t> lost_scans;
  std::size_t lost = 0;
  /// "ok", or "lost" when more than OdometryOptions::max_lost_ratio of the scans were lost.
  std::string tracking = "ok";
  /// Standard deviations (x, y: m; yaw: rad) of the final pose from the propagated covariance.
  double final_sigma_x_m = 0.0, final_sigma_y_m = 0.0, final_sigma_yaw_rad = 0.0;
  /// Scans whose increment's translation 1-sigma exceeded 0.1 m (weakly constrained matches).
  std::size_t weak_scans = 0;
  /// lidarseg, per tracked scan (`ok`, `recovered` or `degenerate`): its motion from the
  /// keyframe it was matched against and that estimate's covariance (robot frame), for the
  /// NEES against a ground truth.
  std::vector<eval::KeyframeMotion> keyframe_motions;
  std::optional<eval::TrajectoryErrors> errors;
  /// The NEES of `keyframe_motions` against the ground truth, when there is one.
  std::optional<eval::NeesSummary> nees;
  std::optional<eval::RelationErrors> relations;
  std::optional<eval::RelationErrors> log_relations;
};

/// Everything a run measured: the counts of its records (RecordCounts: frames, skipped,
/// stamps, warnings), then the methods' figures.
struct OdometryReport : RecordCounts {
  std::string input;
  std::string format;
  std::string sensor;
  /// Wheel-odometry increments rejected as implausible (a jump).
  std::size_t odometry_jumps = 0;
  /// The prior every method started each match from: "constant velocity", or "wheel
  /// odometry" when asked for (--use-odometry) and the log has it. Asked for on a log
  /// without wheel odometry it is "constant velocity (the log has no wheel odometry)".
  std::string prior = "constant velocity";
  /// The beam times the rolling-shutter correction makes from the configuration ([odometry]
  /// scanner_rotation_hz and scan_stamp) for scans without their own, e.g. "scanner at 5 Hz,
  /// stamped at the last beam (scans without their own beam times)"; "off" when it makes
  /// none (a log's own per-beam times still deskew).
  std::string beam_times = "off";
  /// Scans whose prior was the wheel odometry's increment.
  std::size_t odometry_priors = 0;
  /// With allow_truncated: why the log could not be read to its end ("file, entry N: ...");
  /// the results cover the scans before it. Empty when the log was read to its end.
  std::string log_error;
  std::string gt_path;
  std::string relations_path;
  MethodReport lidarseg;
  /// The baselines run beside it, in baselineKinds()' order (Baselines.h): MRPT ICP
  /// keyframed like lidarseg ("icp"), scan to scan ("icp-s2s").
  std::vector<MethodReport> baselines;
  /// The baseline named `name` (MethodReport::name), or nullptr when it was not run.
  const MethodReport* baseline(std::string_view name) const {
    for (const MethodReport& m : baselines) {
      if (m.name == name) return &m;
    }
    return nullptr;
  }
  /// Median keyframed ICP time / median lidarseg time, measured in the same run
  /// (kSpeedupBaseline); 0 without that baseline.
  double speedup_median = 0.0;
  std::vector<std::string> outputs;
};

/// The name the issue tracker and the docs use for the run's report.
using RunReport = OdometryReport;

}  // namespace lidarseg::report
