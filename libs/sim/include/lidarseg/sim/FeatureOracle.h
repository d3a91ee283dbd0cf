#pragma once
/// @file FeatureOracle.h
/// Ground truth of the doors and corners a sensor can see (paper §III.B).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Kinds of features; names as in the detector's output ("door_open", ...).
enum class FeatureType { kDoorOpen, kDoorClosed, kDoorAjar, kCornerConvex, kCornerConcave };
const char* toString(FeatureType type);

/// A feature in the sensor frame.
struct Feature {
  FeatureType type = FeatureType::kCornerConvex;
  /// Doorway centre on the wall line, or the corner point (m).
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  /// Door: direction of the wall through the doorway; corner: direction of the bisector
  /// of its walls, pointing into the free space (rad).
  double theta_rad = 0.0;
  /// Door width (m); 0 for corners.
  double width_m = 0.0;
  /// Index of the door in World::doors(), or of the corner in FeatureOracle::corners().
  std::size_t id = 0;
};

/// A corner of the world: where two walls meet at an angle.
struct Corner {
  Eigen::Vector2d point;
  Eigen::Vector2d toward_a;  ///< unit direction along the first wall
  Eigen::Vector2d toward_b;  ///< unit direction along the second wall
};

/// Which doors and corners of a world a range sensor sees from a pose: in its field of
/// view and range, and not hidden behind a wall.
class FeatureOracle {
 public:
  /// Corners are the shared endpoints of two walls (not clutter) of at least
  /// `min_wall_m`, meeting at 30 to 150 degrees.
  FeatureOracle(const World& world, double min_wall_m = 0.3);

  std::vector<Feature> visible(const Pose2& T_world_sensor, const BeamLayout& layout,
                               double max_range_m) const;

  const std::vector<Corner>& corners() const { return corners_; }

 private:
  bool inView(const Pose2& T_world_sensor, const BeamLayout& layout, double max_range_m,
              const Eigen::Vector2d& p, Eigen::Vector2d& local) const;
  bool reachable(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;

  const World* world_;
  RayCaster caster_;
  std::vector<Corner> corners_;
};

}  // namespace lidarseg::sim
