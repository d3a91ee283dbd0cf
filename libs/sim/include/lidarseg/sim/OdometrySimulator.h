#pragma once
/// @file OdometrySimulator.h
/// Noisy wheel odometry integrated along a true trajectory.

#include <cstdint>
#include <random>

#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Drift of simulated wheel odometry: standard deviations proportional to the motion.
struct OdometryNoise {
  /// Translation error per metre travelled (m/m).
  double translation_per_m = 0.02;
  /// Rotation error per radian turned (rad/rad).
  double rotation_per_rad = 0.02;
  /// Rotation error per metre travelled (rad/m): the slow heading drift of real wheels.
  double rotation_per_m = 0.005;
};

/// Integrates noisy increments of a true trajectory into an odometry pose, which starts
/// equal to the first true pose and drifts from it. Deterministic for a seed.
class OdometrySimulator {
 public:
  OdometrySimulator(const OdometryNoise& noise, std::uint64_t seed) : noise_(noise), rng_(seed) {}

  /// Feeds the next true pose; returns the odometry pose at that time.
  Pose2D update(const Pose2D& true_pose);

 private:
  OdometryNoise noise_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  bool started_ = false;
  Pose2D last_true_;
  Pose2D odometry_;
};

}  // namespace lidarseg::sim
