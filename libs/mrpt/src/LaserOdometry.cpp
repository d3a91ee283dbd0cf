#include "lidarseg/mrpt/LaserOdometry.h"

#include "lidarseg/mrpt/PoseConversion.h"

#include <cmath>
#include <stdexcept>

#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"

#include <mrpt/math/CMatrixFixed.h>

namespace lidarseg::mrpt_adapter {


Pose2D sensorOnRobot(const mrpt::obs::CObservation2DRangeScan& scan) {
  return {scan.sensorPose.x(), scan.sensorPose.y(), scan.sensorPose.yaw()};
}

Eigen::Matrix3d conjugateCovariance(const Pose2D& T, const Eigen::Matrix3d& covariance) {
  Eigen::Matrix3d Ad = Eigen::Matrix3d::Identity();
  const double c = std::cos(T.yaw), s = std::sin(T.yaw);
  Ad(0, 0) = c;
  Ad(0, 1) = -s;
  Ad(1, 0) = s;
  Ad(1, 1) = c;
  Ad(0, 2) = T.y;
  Ad(1, 2) = -T.x;
  return Ad * covariance * Ad.transpose();
}

LaserOdometry::LaserOdometry(const OdometryParams& params) : odometry_(params) {}

void LaserOdometry::reset() {
  odometry_.reset();
  pose_covariance_.setZero();
  keyframe_covariance_.setZero();
  keyframe_pose_ = {};
  robot_pose_ = {};
  first_ = true;
}

LaserOdometryStep LaserOdometry::process(const mrpt::obs::CObservation2DRangeScan& obs,
                                         const std::optional<mrpt::poses::CPose2D>& robot_odometry_increment,
                                         std::optional<double> stamp_s) {
  Scan scan = converter_.convert(obs);
  scan.stamp_s = stamp_s ? *stamp_s : mrpt::Clock::toDouble(obs.timestamp);
  std::optional<Pose2D> increment;
  if (robot_odometry_increment) increment = toPose2D(*robot_odometry_increment);
  return process(scan, sensorOnRobot(obs), increment);
}

LaserOdometryStep LaserOdometry::process(const Scan& scan, const Pose2D& S,
                                         const std::optional<Pose2D>& robot_odometry_increment) {
  const auto usable = [](double v) { return std::isfinite(v) && std::abs(v) <= kMaxRelativeCoordinate; };
  if (!(usable(S.x) && usable(S.y) && usable(S.yaw))) {
    throw std::invalid_argument("LaserOdometry: the sensor's pose on the robot (" + numberText(S.x) + ", " +
                                numberText(S.y) + ", " + numberText(S.yaw) + ") is not finite or beyond +-1e7 (m, rad)");
  }
  LaserOdometryStep out;
  std::optional<Pose2D> prior;
  if (robot_odometry_increment) prior = compose(compose(inverse(S), *robot_odometry_increment), S);
  out.core = odometry_.process(scan, prior);
  // Robot increment = S * sensor increment * S^-1.
  const Pose2D robot_increment = compose(compose(S, out.core.increment), inverse(S));
  const Eigen::Matrix3d increment_cov =
      out.core.first ? Eigen::Matrix3d::Zero() : conjugateCovariance(S, out.core.increment_covariance);
  out.increment = mrpt::poses::CPosePDFGaussian(toMrpt(robot_increment), toMrpt(increment_cov));
  // Robot poses: T_odom_robot = S * T_odom_sensor * S^-1 (odometry frame = the robot
  // frame at the first scan). Covariance: that of the keyframe's pose, propagated through
  // the match against the keyframe (T_key_curr, robot frame) and its covariance.
  const Pose2D robot_pose = compose(compose(S, out.core.T_odom_sensor), inverse(S));
  if (first_ || out.core.first) {
    first_ = false;
    keyframe_pose_ = robot_pose;
    keyframe_covariance_.setZero();
    pose_covariance_.setZero();
  } else {
    // A keyframe revised at this scan (decision 114) is matched against from its revised pose
    // (its covariance stays the one propagated to its first estimate).
    if (out.core.keyframe_revision) {
      keyframe_pose_ = compose(compose(S, out.core.keyframe_revision->T_odom_sensor), inverse(S));
    }
    // The pose kept from the keyframe (refined, or found by the search) and its covariance,
    // not the segment match's, which the refinement replaced.
    const Pose2D from_key = relative(robot_pose, keyframe_pose_);
    const Eigen::Matrix3d match_cov = conjugateCovariance(S, out.core.increment_covariance);
    Eigen::Matrix3d Jp = Eigen::Matrix3d::Identity(), Ji = Eigen::Matrix3d::Identity();
    const double c = std::cos(keyframe_pose_.yaw), s = std::sin(keyframe_pose_.yaw);
    Jp(0, 2) = -s * from_key.x - c * from_key.y;
    Jp(1, 2) = c * from_key.x - s * from_key.y;
    Ji(0, 0) = c;
    Ji(0, 1) = -s;
    Ji(1, 0) = s;
    Ji(1, 1) = c;
    pose_covariance_ = Jp * keyframe_covariance_ * Jp.transpose() + Ji * match_cov * Ji.transpose();
    if (out.core.keyframe) {
      keyframe_pose_ = robot_pose;
      keyframe_covariance_ = pose_covariance_;
    }
  }
  robot_pose_ = toMrpt(robot_pose);
  out.robot_pose = mrpt::poses::CPosePDFGaussian(robot_pose_, toMrpt(pose_covariance_));
  return out;
}

}  // namespace lidarseg::mrpt_adapter
