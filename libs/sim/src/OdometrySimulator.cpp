#include "lidarseg/sim/OdometrySimulator.h"

#include <cmath>

namespace lidarseg::sim {

Pose2D OdometrySimulator::update(const Pose2D& true_pose) {
  if (!started_) {
    started_ = true;
    last_true_ = true_pose;
    odometry_ = true_pose;
    return odometry_;
  }
  Pose2D delta = relative(true_pose, last_true_);
  last_true_ = true_pose;
  const double dist = std::hypot(delta.x, delta.y);
  const double t_sigma = noise_.translation_per_m * dist;
  const double r_sigma = noise_.rotation_per_rad * std::abs(delta.yaw) + noise_.rotation_per_m * dist;
  delta.x += t_sigma * unit_(rng_);
  delta.y += t_sigma * unit_(rng_);
  delta.yaw += r_sigma * unit_(rng_);
  odometry_ = compose(odometry_, delta);
  return odometry_;
}

}  // namespace lidarseg::sim
