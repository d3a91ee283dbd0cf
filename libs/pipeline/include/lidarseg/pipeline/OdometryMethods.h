#pragma once
/// @file
/// lidarseg::pipeline: the odometry methods a run compares, behind one interface.
/// lidarseg (through the MRPT adapter's SegmentAlignment) and MRPT's ICP, keyframed with
/// lidarseg's policy or scan to scan. A new baseline is one more class, one entry of
/// baselineKinds() (Baselines.h) and one line of makeBaseline().

#include <memory>
#include <optional>
#include <string>

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/slam/CICP.h>

#include "lidarseg/report/RunReport.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/SegmentAlignment.h"

namespace lidarseg::pipeline {

/// One scan as every method sees it.
struct ScanInput {
  const mrpt_adapter::LaserRecord& record;
  /// The stamp policy's view of the scan's time (model clock, output stamp, gap).
  StampStep time;
  /// The robot's motion since the previous scan (robot frame) when known: the plausible
  /// wheel-odometry increment, or no motion after a time gap; empty: constant velocity.
  std::optional<Pose2D> prior;
};

/// What a method made of one scan (also appended to its MethodReport).
struct MethodStep {
  double stamp_s = 0.0;  ///< the output stamp (s)
  Pose2D pose;           ///< robot pose in the run's odometry frame (m, rad)
  double time_us = 0.0;  ///< the method's time on the scan (microseconds)
  /// lidarseg: the tracking status ("ok", "degenerate", "recovered", "lost"; "first");
  /// ICP: "converged", "not_converged", "skipped" or "first".
  std::string status;
};

/// An odometry method: robot poses, scan after scan, into its own MethodReport.
class OdometryMethod {
 public:
  virtual ~OdometryMethod() = default;
  /// Processes the next scan: its step, also appended (pose, time, status) to report().
  /// @throws std::invalid_argument when the scan cannot be used (the run then skips it
  ///         for every method, and this method's state is unchanged).
  virtual MethodStep process(const ScanInput& scan) = 0;
  report::MethodReport& report() { return report_; }
  const report::MethodReport& report() const { return report_; }

 protected:
  explicit OdometryMethod(std::string name) { report_.name = std::move(name); }
  report::MethodReport report_;
};

/// lidarseg: segmentation, segment match, refinement, search, run by the MRPT-facing
/// mrpt_adapter::SegmentAlignment's tracking (which accounts for the laser's mounting on
/// the robot), so that the class an MRPT program uses is the one the tools run.
class LidarsegMethod : public OdometryMethod {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit LidarsegMethod(const OdometryParams& params);
  /// The record's scan goes to the odometry on the stamp policy's clock (StampStep's model
  /// stamp): as it is when that is the log's stamp, otherwise through a buffer reused across
  /// scans. The record is not changed.
  MethodStep process(const ScanInput& scan) override;
  /// The last processed scan's step (robot pose, increment, core details).
  const mrpt_adapter::SegmentAlignment::TTrackResult& lastStep() const { return last_; }
  /// The tracking core (the last scan's segmentation, sensor frame); only after a process().
  const SegmentOdometry& core() const { return alignment_.trackingCore(); }

 private:
  MethodStep record(const ScanInput& scan);
  mrpt_adapter::SegmentAlignment alignment_;
  mrpt_adapter::SegmentAlignment::TTrackResult last_;
  Scan timed_;  // a record's scan with a repaired stamp (model clock); reused across scans
  // The keyframe the next scan is matched against: its output stamp and robot pose (the
  // revised one after a revision, decision 114), for MethodReport::keyframe_motions.
  double key_stamp_s_ = 0.0;
  Pose2D key_robot_pose_;
};

/// MRPT ICP as a laser odometry: each scan's points aligned against a reference scan's
/// (the keyframe's, renewed with lidarseg's policy, or the previous scan's), from the same
/// kind of prior as lidarseg.
class IcpMethod : public OdometryMethod {
 public:
  /// keyframed: renew the reference when the motion from it exceeds the distances below
  /// (m, rad) or ICP did not converge; otherwise every scan is the next one's reference.
  IcpMethod(std::string name, const mrpt::slam::CICP::TConfigParams& options, bool keyframed,
            double keyframe_distance_m, double keyframe_angle_rad);
  MethodStep process(const ScanInput& scan) override;

 private:
  Pose2D predictedIncrement(const ScanInput& scan) const;
  mrpt::slam::CICP icp_;
  bool keyframed_;
  double key_distance_, key_angle_;
  std::unique_ptr<mrpt::maps::CSimplePointsMap> reference_;
  Pose2D reference_pose_, pose_, last_increment_;
  double last_dt_ = 0.0;
};

/// The baseline method named `name` (baselineKinds()), configured from `config` (its
/// `[icp]` section; the keyframe policy of its `[odometry]` one).
/// @throws std::invalid_argument for a name no baseline has, listing the known ones.
std::unique_ptr<OdometryMethod> makeBaseline(const std::string& name, const mrpt_adapter::LidarsegConfig& config);

}  // namespace lidarseg::pipeline
