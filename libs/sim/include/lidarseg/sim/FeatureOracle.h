#pragma once
/// @file FeatureOracle.h
/// Ground truth of the doors and corners a sensor can see (paper §III.B).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Feature.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

using lidarseg::FeatureType;

/// A true feature in the sensor frame.
struct Feature {
  FeatureType type = FeatureType::kCornerConvex;
  /// Doorway centre on the wall line, or the corner point (m).
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  /// As lidarseg::Feature: door, the wall's normal pointing away from the sensor; corner,
  /// the bisector of its walls pointing into the free space (rad).
  double theta_rad = 0.0;
  /// Door width (m); 0 for corners.
  double width_m = 0.0;
  /// Index of the door in World::doors(), or of the corner in FeatureOracle::corners().
  std::size_t id = 0;
  /// Whether the scan can show it (FeatureOracleParams): both walls of a corner, or the
  /// walls on both sides of a door, are seen, with enough beams on each and in the gap.
  bool resolvable = false;
  /// What the scan can show it as: its type, except a door ajar whose leaf is out of sight
  /// near the hinge, which looks like an open door.
  FeatureType seen_as = FeatureType::kCornerConvex;
};

/// A corner of the world: where two walls meet at an angle.
struct Corner {
  Eigen::Vector2d point;
  Eigen::Vector2d toward_a;  ///< unit direction along the first wall
  Eigen::Vector2d toward_b;  ///< unit direction along the second wall
  double length_a = 0.0;     ///< length of the first wall from the corner (m)
  double length_b = 0.0;
};

/// What counts as a corner, and when a feature is resolvable by a scan. The defaults
/// match FeatureDetectorParams' defaults; the rules are in docs/features.md.
struct FeatureOracleParams {
  /// Walls shorter than this make no corner (m).
  double min_wall_m = 0.25;
  /// A wall ending this close to another one's side touches it (m): a bin against a wall
  /// makes corners with it; nothing passes, and no scan resolves, such a gap.
  double touch_m = 0.05;
  /// Range of the angle between the two walls of a corner (deg).
  double corner_min_angle_deg = 45.0;
  double corner_max_angle_deg = 135.0;
  /// Resolvable corner: on each wall, the first min(wall, arm_check_m) metres are seen
  /// and hold at least min_arm_beams beams.
  double arm_check_m = 1.0;
  std::size_t min_arm_beams = 5;
  /// Resolvable door: the doorway holds at least min_gap_beams beams, and the wall on each
  /// side is seen over wall_check_m next to the jamb with at least min_wall_beams beams.
  std::size_t min_gap_beams = 3;
  double wall_check_m = 0.5;
  std::size_t min_wall_beams = 4;
  /// A door ajar is seen as one when its leaf's first leaf_check_m from the hinge are seen
  /// with at least min_gap_beams beams (either leaf of a double door).
  double leaf_check_m = 0.3;
  /// Corners this close to a door's jamb, on either face of its wall, belong to the door
  /// (the reveals of a thick wall meet the wall's faces there): no corner, as the
  /// detector's corner_door_exclusion_m (m).
  double door_exclusion_m = 0.2;
};

/// Which doors and corners of a world a range sensor sees from a pose: in its field of
/// view and range, and not hidden behind a wall.
class FeatureOracle {
 public:
  /// Corners: two walls (not door leaves) of at least min_wall_m sharing an endpoint, or
  /// one's endpoint on the other's interior (a T: two corners), or crossing (an X: four),
  /// at an angle in range.
  explicit FeatureOracle(const World& world, const FeatureOracleParams& params = {});

  std::vector<Feature> visible(const Pose2D& T_world_sensor, const BeamLayout& layout,
                               double max_range_m) const;

  const std::vector<Corner>& corners() const { return corners_; }
  const FeatureOracleParams& params() const { return params_; }

 private:
  bool inView(const Pose2D& T_world_sensor, const BeamLayout& layout, double max_range_m,
              const Eigen::Vector2d& p, Eigen::Vector2d& local) const;
  bool reachable(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;
  /// Seen from `from` over its whole length (both ends and the middle reachable) and
  /// spanning at least `min_beams` beams of angular step `step_rad`.
  bool seenWithBeams(const Eigen::Vector2d& from, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     double step_rad, std::size_t min_beams) const;

  const World* world_;
  FeatureOracleParams params_;
  RayCaster caster_;
  std::vector<Corner> corners_;
};

}  // namespace lidarseg::sim
