#pragma once
/// @file World.h
/// A planar world made of straight walls, for simulating range scans.

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Pose2D.h"

namespace lidarseg::sim {

/// What a wall is made of, for rendering and ground truth.
enum class SurfaceKind : unsigned char {
  kWall,     ///< a wall (including a door recess's sides)
  kDoor,     ///< a door leaf
  kClutter,  ///< boxes, bins, pillars
};

/// A wall: a straight segment in the world frame (m).
struct Wall {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  SurfaceKind kind = SurfaceKind::kWall;
};

/// A 2D pose (m, m, rad): the frame's origin and heading in its parent frame.

/// Kinds of doors a world can hold (the paper's §III.B features).
enum class DoorKind { kOpen, kClosed, kAjar };

/// "open", "closed" or "ajar".
const char* toString(DoorKind kind);

/// A door in a wall, in the world frame. The opening runs from jamb_a to jamb_b on the
/// wall's line; "behind" is the left side of jamb_a -> jamb_b.
struct Door {
  DoorKind kind = DoorKind::kOpen;
  Eigen::Vector2d jamb_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d jamb_b = Eigen::Vector2d::Zero();
  /// Closed door: depth of the recess behind the wall line (m). Unused otherwise.
  double recess_m = 0.0;
  /// Ajar door: angle of the leaf, hinged at jamb_a, from the closed position (rad).
  double leaf_angle_rad = 0.0;

  double width() const { return (jamb_b - jamb_a).norm(); }
  Eigen::Vector2d centre() const { return 0.5 * (jamb_a + jamb_b); }
};

/// A set of walls (and the doors they contain) in the world frame.
class World {
 public:
  World() = default;
  explicit World(std::vector<Wall> walls) : walls_(std::move(walls)) {}

  /// Adds a door: cuts the opening out of the walls lying on its line (within 1 mm) and
  /// adds its geometry: nothing for an open door, the two recess sides and the leaf for a
  /// closed one, the leaf for an ajar one.
  void addDoor(const Door& door);
  const std::vector<Door>& doors() const { return doors_; }

  void addWall(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
               SurfaceKind kind = SurfaceKind::kWall) {
    walls_.push_back({a, b, kind});
  }
  /// Adds the closed polygon p0-p1-...-pn-p0.
  void addPolygon(const std::vector<Eigen::Vector2d>& corners,
                  SurfaceKind kind = SurfaceKind::kWall);
  /// Adds the polyline p0-p1-...-pn (open).
  void addPolyline(const std::vector<Eigen::Vector2d>& corners,
                   SurfaceKind kind = SurfaceKind::kWall);

  const std::vector<Wall>& walls() const { return walls_; }

  /// Distance (m) along the ray from `origin` in direction `unit_dir` (world frame) to the
  /// nearest wall, or +infinity when it hits none. Exact ray-segment intersection;
  /// O(number of walls).
  double castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& unit_dir) const;

 private:
  std::vector<Wall> walls_;
  std::vector<Door> doors_;
};

}  // namespace lidarseg::sim
