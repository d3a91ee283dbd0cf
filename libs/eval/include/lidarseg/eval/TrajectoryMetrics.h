#pragma once
/// @file TrajectoryMetrics.h
/// Errors of an estimated trajectory against ground truth: the paper's Table I (per-scan
/// motion errors, §IV.B), the final position error and the absolute trajectory error.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/eval/StampedTrajectory.h"

namespace lidarseg::eval {

/// Per-scan motion errors (paper Table I): for each pair of consecutive associated poses,
/// the absolute difference between the estimated and the true motion, per component, in
/// the robot frame of the earlier pose. Means and standard deviations of these.
struct MotionErrors {
  Summary dx_m;
  Summary dy_m;
  Summary dtheta_rad;
};

/// Every error of one trajectory.
struct TrajectoryErrors {
  /// Estimated poses that found a ground-truth pose within the tolerance.
  std::size_t associated = 0;
  /// Length of the ground-truth path over the associated poses (m).
  double path_length_m = 0.0;
  /// Position and heading error of the last pose, with the first poses made to coincide
  /// (the paper's "final error"; m, rad).
  double final_position_error_m = 0.0;
  double final_yaw_error_rad = 0.0;
  /// Absolute trajectory error: RMSE / mean / max of the position error after the
  /// least-squares rigid alignment of the whole trajectory (m).
  double ate_rmse_m = 0.0;
  double ate_mean_m = 0.0;
  double ate_max_m = 0.0;
  MotionErrors motion;
};

/// Associates each estimated pose with the ground-truth pose nearest in time (within
/// `tolerance_s`) and computes every error.
/// @throws std::invalid_argument when fewer than 2 poses associate.
TrajectoryErrors evaluateTrajectory(const StampedTrajectory& estimate,
                                    const StampedTrajectory& ground_truth, double tolerance_s = 0.005);

/// What a keyframe-based odometry measured at one scan: its motion from the keyframe it was
/// matched against, T_keyframe_curr (robot frame of the keyframe; x, y in m, yaw in rad),
/// with that estimate's covariance (same order and units).
struct KeyframeMotion {
  double keyframe_stamp_s = 0.0;
  double stamp_s = 0.0;
  Pose2D T_key_curr;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// The normalised estimation error squared (NEES) of keyframe motions against the ground
/// truth: e^T C^-1 e, e the estimate minus the true T_keyframe_curr (yaw wrapped). For a
/// consistent estimator it follows a chi-square with 3 degrees of freedom: mean 3, 95 % of
/// the draws at or below 7.815 (issue 14, "honest uncertainty").
struct NeesSummary {
  /// Motions whose two stamps found a ground-truth pose and whose covariance is positive
  /// definite; `singular` counts those left out for their covariance alone.
  std::size_t evaluated = 0, singular = 0;
  double mean = 0.0, median = 0.0;
  /// Share of the evaluated motions whose NEES is at or below 7.815.
  double share_within_95 = 0.0;
};

/// The NEES of every motion whose stamps associate with `ground_truth` within `tolerance_s`.
/// Empty input or no association gives evaluated = 0 and zero figures.
NeesSummary evaluateNees(const std::vector<KeyframeMotion>& motions, const StampedTrajectory& ground_truth,
                         double tolerance_s = 0.005);

/// The rigid transform T minimising sum |T * a_i - b_i|^2 over positions (2D Horn/Umeyama,
/// no scale). Requires a.size() == b.size() >= 1.
Pose2D alignPositions(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b);

}  // namespace lidarseg::eval
