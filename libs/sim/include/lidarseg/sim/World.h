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
  /// Thickness of the wall the door is in (m): the opening is also cut out of the wall
  /// face on the parallel line this far behind, and the opening's sides (reveals) join
  /// the two faces. 0: a wall of no thickness (the reveals are only the recess's sides).
  double wall_thickness_m = 0.0;
  /// Two leaves of half the width each, hinged at jamb_a and jamb_b. Ajar: the second
  /// leaf is opened by second_leaf_angle_rad. Closed and open doors look the same either way.
  bool double_leaf = false;
  double second_leaf_angle_rad = 0.0;

  /// Hinge of an ajar door's leaf (of the first leaf of a double door): jamb_a, moved
  /// recess_m behind the wall line (the frame's depth).
  Eigen::Vector2d hingeA() const;
  /// Hinge of the second leaf of a double door: jamb_b moved recess_m behind.
  Eigen::Vector2d hingeB() const;
  /// Unit normal pointing behind the door (the left of jamb_a -> jamb_b).
  Eigen::Vector2d behind() const;

  double width() const { return (jamb_b - jamb_a).norm(); }
  Eigen::Vector2d centre() const { return 0.5 * (jamb_a + jamb_b); }
};

/// True when the openings of `a` and `b` lie on the same line (within 1 mm, the tolerance
/// World::addDoor cuts walls with) and share more than 1 mm of it: one opening cut twice,
/// whatever the doors' kinds. Doors that only share a jamb do not overlap.
bool overlap(const Door& a, const Door& b);

/// A set of walls (and the doors they contain) in the world frame.
class World {
 public:
  World() = default;
  explicit World(std::vector<Wall> walls) : walls_(std::move(walls)) {}

  /// Adds a door: cuts the opening out of the walls lying on its line (within 1 mm), and
  /// on the line wall_thickness_m behind when the wall is thick, and adds its geometry:
  /// the reveals (the opening's two sides, max(recess_m, wall_thickness_m) deep; none for
  /// an open door in a wall of no thickness), the leaf of a closed door recess_m behind the
  /// wall line, the leaf (or two leaves) of an ajar one hinged recess_m behind the jambs.
  void addDoor(const Door& door);
  const std::vector<Door>& doors() const { return doors_; }
  /// True when a wall lies on the door's line (within 1 mm) and overlaps its opening by
  /// more than 1 mm: addDoor would cut it. O(number of walls).
  bool holdsDoor(const Door& door) const;
  /// How much of the door's width (m) the walls along its jambs' line cover (the walls'
  /// shares summed: at most the width when they do not overlap); a door in one wall is
  /// covered whole, a door reaching past its wall's end is not.
  double wallAlongDoor(const Door& door) const;

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
