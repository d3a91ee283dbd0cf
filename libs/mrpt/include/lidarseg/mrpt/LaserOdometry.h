#pragma once
/// @file LaserOdometry.h
/// lidarseg's laser odometry on MRPT observations: robot poses with covariances.

#include <optional>

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::mrpt_adapter {

/// One processed scan, in the robot frame.
struct LaserOdometryStep {
  /// The core step (sensor frame, matching details, stage timings).
  OdometryStep core;
  /// Robot pose in the odometry frame (the robot frame at the first scan), with the
  /// covariance accumulated along the way.
  mrpt::poses::CPosePDFGaussian robot_pose;
  /// Robot motion since the previous scan with its covariance (robot frame).
  mrpt::poses::CPosePDFGaussian increment;
};

/// Feeds `CObservation2DRangeScan`s one at a time to lidarseg::SegmentOdometry (each scan
/// segmented once; the keyframe's segments reused) and returns robot poses: the laser's
/// pose on the robot (`sensorPose`) is taken into account, so the trajectory is the
/// robot's, comparable with wheel odometry and ground truth.
class LaserOdometry {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit LaserOdometry(const OdometryParams& params = {});

  /// Processes the next scan.
  /// @param robot_odometry_increment wheel odometry of the robot since the previous scan
  ///        (robot frame), used as the prior instead of constant velocity.
  /// @throws std::invalid_argument for a scan that cannot be converted (fewer than 2
  ///         beams, bad aperture); the odometry's state is unchanged then.
  /// @param stamp_s the scan's time for the motion model (s); empty: its own timestamp.
  /// The same step on a core scan (sensor frame, `scan.stamp_s` the model's clock) from a
  /// sensor mounted at `sensor_on_robot` (T_robot_sensor), as a log reader's ScanRecord
  /// gives them: no MRPT observation is converted.
  LaserOdometryStep process(const Scan& scan, const Pose2D& sensor_on_robot,
                            const std::optional<Pose2D>& robot_odometry_increment = {});

  LaserOdometryStep process(const mrpt::obs::CObservation2DRangeScan& scan,
                            const std::optional<mrpt::poses::CPose2D>& robot_odometry_increment = {},
                            std::optional<double> stamp_s = {});

  /// The underlying core odometry (segmentations, velocity).
  const SegmentOdometry& core() const { return odometry_; }
  void reset();

 private:
  SegmentOdometry odometry_;
  ScanConverter converter_;
  Eigen::Matrix3d pose_covariance_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d keyframe_covariance_ = Eigen::Matrix3d::Zero();
  Pose2D keyframe_pose_;
  mrpt::poses::CPose2D robot_pose_;
  bool first_ = true;
};

/// The 2D pose of a laser on its robot (the planar part of `sensorPose`).
Pose2D sensorOnRobot(const mrpt::obs::CObservation2DRangeScan& scan);

/// Covariance of T * X * T^-1 given that of X (x, y, yaw), for a fixed T: the adjoint.
Eigen::Matrix3d conjugateCovariance(const Pose2D& T, const Eigen::Matrix3d& covariance);

}  // namespace lidarseg::mrpt_adapter
