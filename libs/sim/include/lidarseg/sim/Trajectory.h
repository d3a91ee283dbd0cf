#pragma once
/// @file Trajectory.h
/// A robot path through waypoints at constant speed, with rounded corners.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// A path through waypoints (world frame, m) driven at constant linear speed; each corner
/// is rounded by a circular arc of the turn radius (smaller where the legs are short), so
/// the heading is continuous and the angular speed is speed / radius in the turns.
class Trajectory {
 public:
  /// @throws std::invalid_argument for fewer than 2 waypoints, two equal consecutive
  /// waypoints, a non-positive speed or a negative radius.
  Trajectory(std::vector<Eigen::Vector2d> waypoints, double speed_mps, double turn_radius_m);

  /// Total length (m) and duration (s).
  double length() const { return length_; }
  double duration() const { return length_ / speed_; }
  double speed() const { return speed_; }

  /// Robot pose at time t (s from the start), t clamped to [0, duration()].
  Pose2D poseAt(double t) const;
  /// Pose at arc length s (m), clamped to [0, length()].
  Pose2D poseAtDistance(double s) const;

  /// The waypoints, as given.
  const std::vector<Eigen::Vector2d>& waypoints() const { return waypoints_; }
  /// The leg (0 = waypoints 0 to 1) that the path at arc length s (m) belongs to; a rounded
  /// corner belongs to the leg it leaves.
  std::size_t legAtDistance(double s) const;
  /// The path as a polyline of (arc length (m), point (world frame, m)): the straight
  /// pieces' ends, and each arc's chords, none further than `tolerance_m` from the arc.
  std::vector<std::pair<double, Eigen::Vector2d>> polyline(double tolerance_m) const;

 private:
  struct Piece {
    Eigen::Vector2d start;   // start point
    double heading = 0.0;    // heading at the start (rad)
    double length = 0.0;     // m
    double curvature = 0.0;  // 1/m, signed (left turns positive); 0 for a straight piece
    double s0 = 0.0;         // arc length at the start
    std::size_t leg = 0;     // the leg (waypoints leg, leg + 1) it lies on or leaves
  };
  std::vector<Eigen::Vector2d> waypoints_;
  std::vector<Piece> pieces_;
  double length_ = 0.0;
  double speed_ = 1.0;
};

/// Where a path first passes through a wall or a door leaf of a world.
struct WallCrossing {
  double s_m = 0.0;                             ///< arc length from the path's start (m)
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< where (world frame, m)
  std::size_t wall = 0;                         ///< index in World::walls()
};

/// The first place where `trajectory` (the robot's centre) crosses or touches one of the
/// world's walls, door leaves or clutter; none when it passes only through openings. The
/// arcs are checked on chords within 1 mm of them. O(path pieces x walls).
std::optional<WallCrossing> firstWallCrossing(const World& world, const Trajectory& trajectory);

/// The clutter (pillar, box: closed outlines) holding `point` (world frame, m): the index in
/// World::walls() of one side of its outline, or none when the point is outside all clutter.
/// A path that starts inside clutter and never crosses its outline (firstWallCrossing())
/// runs wholly inside it. By parity along a ray: a point inside two overlapping pieces
/// counts as outside.
std::optional<std::size_t> clutterHolding(const World& world, const Eigen::Vector2d& point);

/// Reads a trajectory file: `speed V` (m/s), `turn_radius R` (m) and one `waypoint X Y`
/// per line, `#` comments.
/// @throws std::runtime_error "file:line: message" for a bad line, or naming the file.
Trajectory loadTrajectoryFile(const std::string& path);

}  // namespace lidarseg::sim
