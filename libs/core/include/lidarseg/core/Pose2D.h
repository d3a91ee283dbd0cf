#pragma once
#include "lidarseg/core/Angles.h"
/// @file Pose2D.h
/// Planar rigid transforms.

#include <cmath>

#include <Eigen/Core>

namespace lidarseg {

/// A planar pose or rigid transform (m, m, rad). As a transform named T_a_b, it maps
/// coordinates in frame b to frame a: p_a = R(yaw) p_b + (x, y).
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  Eigen::Vector2d translation() const { return {x, y}; }
  /// Applies the transform to a point.
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
};

/// A planar velocity in a body frame: linear (m/s) along x and y, angular (rad/s).
struct Twist2D {
  double vx = 0.0;
  double vy = 0.0;
  double omega = 0.0;

  /// The motion after dt seconds at this constant velocity, to first order (T_t0_t).
  Pose2D integrate(double dt) const { return {vx * dt, vy * dt, omega * dt}; }
};

/// Angle wrapped to (-pi, pi].
inline double wrapAngle(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

/// T_a_c = T_a_b (+) T_b_c.
inline Pose2D compose(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrapAngle(a.yaw + b.yaw)};
}

/// T_b_a from T_a_b.
inline Pose2D inverse(const Pose2D& a) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, wrapAngle(-a.yaw)};
}

/// Pose a expressed in frame b: T_b_a = inverse(T_w_b) (+) T_w_a.
inline Pose2D relative(const Pose2D& a, const Pose2D& b) { return compose(inverse(b), a); }

}  // namespace lidarseg
