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

#include "lidarseg/report/RunReport.h"

namespace lidarseg::mrpt_adapter {
class LaserLogReader;
}

namespace lidarseg::pipeline {
class OdometryRun;
struct RunSettings;
}  // namespace lidarseg::pipeline

namespace lidarseg::report {
class OutputSet;
struct RunReferences;
}  // namespace lidarseg::report

namespace lidarseg::apps {

using report::OutputSet;
/// The report lidarseg-odometry's run returns (lidarseg::pipeline's, one for every tool).
using report::MethodReport;
using report::OdometryReport;

/// The range of --scanner-hz (besides 0, no correction): a 2D scanner turns at a few to a
/// few hundred revolutions per second.
inline constexpr double kMinScannerHz = 0.1;
inline constexpr double kMaxScannerHz = 1000.0;
/// The largest --relations-tolerance (s): a relation's stamps are matched to scans within it;
/// Freiburg relations are at most a few seconds apart, so a second pairs unrelated scans.
inline constexpr double kMaxRelationsToleranceS = 0.5;

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
  /// How far (s) a relation's stamp may be from a scan's to pair with it; (0, 0.5].
  double relations_tolerance_s = 0.01;
  /// Use the poses written in the log (CARMEN laser lines; the corrected poses of
  /// "corrected" logs) as the reference of a per-scan relative-motion evaluation.
  bool log_reference = false;
  /// Write the input back (gzip, as MRPT writes rawlogs) with lidarseg's odometry as the
  /// robot's movement, stamped with the repaired stamps of the TUM files.
  std::string write_rawlog;
  /// With write_rawlog: add the doors and corners of each scan as a CObservationBearingRange
  /// (landmarks for MRPT's EKF SLAM). Off by default: icp-slam and pf-localization want
  /// the scans only.
  bool write_landmarks = false;
  /// Doors and corners of every scan (the [features] section of the configuration), robot
  /// frame: `t,type,x,y,theta,width,confidence,scan,var_x,var_y,cov_xy,var_theta,var_width`.
  std::string features_out;
  /// Scanner rotation frequency for rolling-shutter correction (Hz); none: the config's, 0 =
  /// none, else from kMinScannerHz to kMaxScannerHz (another value is a usage error).
  std::optional<double> scanner_rotation_hz;
  /// Which beam's instant the log's stamps are ("first", "middle", "last"); empty: the
  /// configuration's [odometry] scan_stamp.
  std::string scan_stamp;
  /// Progress on stderr (only shown when stderr is a terminal).
  bool progress = true;
  /// Draw PNG pictures in out_dir.
  bool plots = true;
  /// A log that ends in a truncated or corrupt entry (a recording cut by a power loss):
  /// false = an error and no output; true = the scans before it are processed, the outputs
  /// written, and the message kept in OdometryReport::log_error.
  bool allow_truncated = false;
  /// A run that loses more than this share of its scans is reported as lost
  /// ("tracking": "lost"), on stderr and without a headline speed-up.
  double max_lost_ratio = 0.01;
};

/// Runs lidarseg (and optionally MRPT ICP) over a log and writes the outputs.
class OdometryApp {
 public:
  explicit OdometryApp(OdometryOptions options);
  /// @throws std::runtime_error / std::invalid_argument naming the file and entry/line
  /// or key when the input cannot be read to the end or the configuration is invalid;
  /// then no output is written. Scans that cannot be processed are skipped and counted.
  OdometryReport run();

 private:
  report::RunReferences readReferences();
  void claimOutputs(OutputSet& outputs) const;
  void processLog(mrpt_adapter::LaserLogReader& reader, pipeline::OdometryRun& odometry, const pipeline::RunSettings& settings,
                  OutputSet& outputs);
  void collectReaderCounts(const mrpt_adapter::LaserLogReader& reader, OdometryReport& report) const;
  void writeOutputs(OdometryReport& report, const report::RunReferences& refs, const eval::StampedTrajectory& log_poses,
                    const eval::StampedTrajectory& wheel_odometry, OutputSet& outputs) const;

  OdometryOptions options_;
  std::string gt_path_;    // the ground truth used (given or found beside the input)
  std::string log_error_;  // with allow_truncated: why the log ended early
};

}  // namespace lidarseg::apps
