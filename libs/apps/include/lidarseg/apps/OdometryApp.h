#pragma once
/// @file OdometryApp.h
/// The logic of `lidarseg-odometry`: laser odometry of a log with lidarseg and, in the
/// same run, with MRPT's ICP; trajectories, timings and errors against ground truth.

#include <cstddef>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/eval/Relations.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/eval/TrajectoryMetrics.h"

namespace lidarseg::apps {

/// Command-line options of `lidarseg-odometry`.
struct OdometryOptions {
  /// MRPT .rawlog (either layout) or CARMEN log (.clf/.log, optionally .gz).
  std::string input;
  /// INI/YAML with [segmentation], [matcher], [odometry] and [icp] sections (each optional).
  std::string config_path;
  /// Rawlog sensor label or CARMEN laser type; empty = the first laser met.
  std::string sensor;
  /// Stop after this many scans (0 = all).
  std::size_t max_scans = 0;
  /// Also run MRPT's CICP on the same scans with the same prior and the same keyframe policy
  /// as lidarseg ([odometry] keyframe_distance_m / keyframe_angle_rad): "icp".
  bool baseline_icp = false;
  /// Also run MRPT's CICP scan to scan (every scan against the previous one): "icp-s2s".
  bool baseline_icp_s2s = false;
  /// Use the log's wheel odometry as the prior of both methods (default: constant velocity).
  bool use_odometry = false;
  /// Output folder (created); empty = no files.
  std::string out_dir;
  /// Ground truth (TUM); empty = PREFIX.gt.tum beside PREFIX.rawlog when it exists.
  std::string gt_path;
  bool auto_gt = true;
  /// Freiburg relations file to evaluate both trajectories on.
  std::string relations_path;
  double relations_tolerance_s = 0.01;
  /// Use the poses written in the log (CARMEN laser lines; the corrected poses of
  /// "corrected" logs) as the reference of a per-scan relative-motion evaluation.
  bool log_reference = false;
  /// Write the input back with lidarseg's odometry as the robot's movement, and the doors
  /// and corners of each scan as a CObservationBearingRange (landmarks for MRPT's EKF SLAM).
  std::string write_rawlog;
  /// Doors and corners of every scan (the [features] section of the configuration), robot
  /// frame: `t,type,x,y,theta,width,confidence,scan,var_x,var_y,cov_xy,var_theta,var_width`.
  std::string features_out;
  /// Scanner rotation frequency for rolling-shutter correction (Hz); < 0 = the config's.
  double scanner_rotation_hz = -1.0;
  /// Which beam's instant the log's stamps are ("first", "middle", "last"); empty: the
  /// configuration's [odometry] scan_stamp.
  std::string scan_stamp;
  /// Progress on stderr (only shown when stderr is a terminal).
  bool progress = true;
  /// Draw PNG pictures in out_dir.
  bool plots = true;
  /// Time gap between scans beyond which the motion prior restarts from rest (s).
  double max_time_gap_s = 1.0;
  /// Speed beyond which an odometry increment is implausible (m/s, rad/s).
  double max_speed_mps = 10.0;
  double max_turn_rate_radps = 10.0;
  /// A log that ends in a truncated or corrupt entry (a recording cut by a power loss):
  /// false = an error and no output; true = the scans before it are processed, the outputs
  /// written, and the message kept in OdometryReport::log_error.
  bool allow_truncated = false;
  /// A run that loses more than this share of its scans is reported as lost
  /// ("tracking": "lost"), on stderr and without a headline speed-up.
  double max_lost_ratio = 0.01;
};

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
  /// lidarseg: the index of every lost scan (the first 1000).
  std::vector<std::size_t> lost_scans;
  std::size_t lost = 0;
  /// "ok", or "lost" when more than OdometryOptions::max_lost_ratio of the scans were lost.
  std::string tracking = "ok";
  /// Standard deviations (x, y: m; yaw: rad) of the final pose from the propagated covariance.
  double final_sigma_x_m = 0.0, final_sigma_y_m = 0.0, final_sigma_yaw_rad = 0.0;
  /// Scans whose increment's translation 1-sigma exceeded 0.1 m (weakly constrained matches).
  std::size_t weak_scans = 0;
  std::optional<eval::TrajectoryErrors> errors;
  std::optional<eval::RelationErrors> relations;
  std::optional<eval::RelationErrors> log_relations;
};

/// Everything a run measured.
struct OdometryReport {
  std::string input;
  std::string format;
  std::string sensor;
  std::size_t frames = 0;
  /// Scans or lines skipped, with where and why (the first 100), and the count.
  std::vector<std::string> skipped;
  std::size_t skipped_count = 0;
  /// Scans whose time did not increase (processed with a synthetic time step).
  std::size_t non_increasing_stamps = 0;
  /// Time gaps beyond max_time_gap_s (the prior restarted from rest).
  std::size_t time_gaps = 0;
  /// Wheel-odometry increments rejected as implausible (a jump).
  std::size_t odometry_jumps = 0;
  std::vector<std::string> warnings;
  /// With allow_truncated: why the log could not be read to its end ("file, entry N: ...");
  /// the results cover the scans before it. Empty when the log was read to its end.
  std::string log_error;
  std::string gt_path;
  std::string relations_path;
  MethodReport lidarseg;
  /// MRPT ICP keyframed like lidarseg ("icp"), and scan to scan ("icp-s2s").
  std::optional<MethodReport> icp;
  std::optional<MethodReport> icp_s2s;
  /// Median keyframed ICP time / median lidarseg time, measured in the same run.
  double speedup_median = 0.0;
  std::vector<std::string> outputs;
};

/// Runs lidarseg (and optionally MRPT ICP) over a log and writes the outputs.
class OdometryApp {
 public:
  explicit OdometryApp(OdometryOptions options);
  /// @throws std::runtime_error / std::invalid_argument naming the file and entry/line
  /// or key when the input cannot be read to the end or the configuration is invalid;
  /// then no output is written. Scans that cannot be processed are skipped and counted.
  OdometryReport run();
  /// A readable summary (the Markdown table and counts).
  static void print(const OdometryReport& report, std::ostream& os);
  /// The results as a Markdown table (paper Table I columns plus final error and ATE).
  static std::string markdownTable(const OdometryReport& report);
  /// summary.json.
  static std::string summaryJson(const OdometryReport& report);

 private:
  OdometryOptions options_;
};

}  // namespace lidarseg::apps
