#pragma once
/// @file World.h
/// A planar world made of straight walls, for simulating range scans.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace lidarseg::sim {

/// A wall: a straight segment in the world frame (m).
struct Wall {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
};

/// A 2D pose (m, m, rad): the frame's origin and heading in its parent frame.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

/// A set of walls in the world frame.
class World {
 public:
  World() = default;
  explicit World(std::vector<Wall> walls) : walls_(std::move(walls)) {}

  void addWall(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { walls_.push_back({a, b}); }
  /// Adds the closed polygon p0-p1-...-pn-p0.
  void addPolygon(const std::vector<Eigen::Vector2d>& corners);
  /// Adds the polyline p0-p1-...-pn (open).
  void addPolyline(const std::vector<Eigen::Vector2d>& corners);

  const std::vector<Wall>& walls() const { return walls_; }

  /// Distance (m) along the ray from `origin` in direction `unit_dir` (world frame) to the
  /// nearest wall, or +infinity when it hits none. Exact ray-segment intersection;
  /// O(number of walls).
  double castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& unit_dir) const;

 private:
  std::vector<Wall> walls_;
};

}  // namespace lidarseg::sim
