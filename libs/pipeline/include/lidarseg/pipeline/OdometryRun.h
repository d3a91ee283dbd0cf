#pragma once
/// @file
/// lidarseg::pipeline: the one run loop of every tool. Records in (from any log
/// reader), stamps repaired, the prior chosen, every method run on the same scan; the
/// report out. lidarseg-odometry, the batch runner (through it) and the inspector all run
/// this class, so one log gives one trajectory everywhere.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/pipeline/OdometryMethods.h"
#include "lidarseg/report/RecordGate.h"
#include "lidarseg/report/RunReport.h"
#include "lidarseg/mrpt/LidarsegConfig.h"

namespace lidarseg::pipeline {

/// What a run compares and how.
struct RunSettings {
  mrpt_adapter::LidarsegConfig config;
  /// The log's wheel odometry as every method's prior (default: constant velocity).
  bool use_odometry = false;
  /// The baselines to run beside lidarseg, by name (baselineKinds(): "icp", MRPT ICP
  /// keyframed with lidarseg's policy; "icp-s2s", scan to scan); reported in that order.
  std::vector<std::string> baselines;
};

/// The outcome of one record.
struct RunStep {
  /// False: the scan could not be used (skipped, counted with the reason).
  bool processed = false;
  /// The stamp policy's view of it.
  StampStep time;
  /// Why it was skipped.
  std::string error;
  /// When processed: each method's step, lidarseg's first, then the baselines' in the
  /// report's order.
  std::vector<MethodStep> steps;
};

class OdometryRun {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit OdometryRun(const RunSettings& settings);
  /// Processes the next record of the log (records must come in the log's order).
  RunStep process(const mrpt_adapter::LaserRecord& record);
  /// lidarseg's method: its last step and segmentation.
  const LidarsegMethod& lidarseg() const { return *lidarseg_; }
  /// Counts of the run so far (frames, stamps, skipped scans, warnings): its RecordGate's.
  const report::RecordCounts& counts() const { return gate_.counts(); }
  /// The poses the log holds beside its scans (CARMEN "corrected" logs), at the output stamps.
  const eval::StampedTrajectory& logPoses() const { return log_poses_; }
  /// The log's wheel odometry of every processed scan that has one (robot poses in the
  /// log's odometry frame), at the output stamps.
  const eval::StampedTrajectory& wheelOdometry() const { return wheel_odometry_; }
  /// Median model time step between scans (s); 0.1 before two scans.
  double medianStep() const;
  /// Ends the run: the counts with every method's report moved in (lidarseg, then the
  /// baselines), time summaries computed and the tracking verdict given.
  report::OdometryReport finish(double max_lost_ratio);

 private:
  // A record's prior and where it came from, counted once the scan is used.
  struct PriorChoice {
    std::optional<Pose2D> prior;
    bool from_odometry = false;
    std::string jump;  // the warning when the wheel odometry jumped
  };
  PriorChoice priorOf(const mrpt_adapter::LaserRecord& record, const StampStep& time) const;
  RunSettings settings_;
  report::RecordGate gate_;
  std::size_t odometry_jumps_ = 0;
  std::size_t odometry_priors_ = 0;  // scans whose prior was the wheel odometry's
  std::unique_ptr<LidarsegMethod> lidarseg_;
  std::vector<std::unique_ptr<OdometryMethod>> baselines_;
  eval::StampedTrajectory log_poses_, wheel_odometry_;
  std::optional<Pose2D> last_odometry_;
  std::vector<double> steps_;
};

}  // namespace lidarseg::pipeline
