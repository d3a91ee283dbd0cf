#pragma once
/// @file Feature.h
/// Doors and corners: the places where a person may suddenly appear (paper §III.B).

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

namespace lidarseg {

/// Kinds of features, as written in feature files ("door_open", ...).
enum class FeatureType : std::uint8_t {
  kDoorOpen,       ///< a doorway with nothing in it: the beams reach beyond the wall line
  kDoorClosed,     ///< a door leaf in a recess, parallel to the wall and a little behind it
  kDoorAjar,       ///< a leaf hinged at a jamb, turned into the room
  kCornerConvex,   ///< two walls meeting, the corner pointing towards the sensor
  kCornerConcave,  ///< two walls meeting, the sensor inside their angle
};

/// Number of feature types.
inline constexpr std::size_t kNumFeatureTypes = 5;

/// "door_open", "door_closed", "door_ajar", "corner_convex" or "corner_concave".
const char* toString(FeatureType type);
/// The type of that name; empty for an unknown name.
std::optional<FeatureType> featureTypeFromString(const std::string& name);
/// True for the three door types.
inline bool isDoor(FeatureType type) {
  return type == FeatureType::kDoorOpen || type == FeatureType::kDoorClosed ||
         type == FeatureType::kDoorAjar;
}

/// A door or a corner detected in one scan, in the sensor frame (m, rad).
struct Feature {
  FeatureType type = FeatureType::kCornerConcave;
  /// Door: the doorway's centre on the wall line. Corner: the intersection of the two
  /// walls' lines (m).
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  /// Door: direction of the wall's normal pointing away from the sensor, through the
  /// doorway. Corner: direction of the bisector of the two walls pointing into the free
  /// space (towards the sensor's side). In (-pi, pi] (rad).
  double theta_rad = 0.0;
  /// Door: distance between the jambs (m). Corner: 0.
  double width_m = 0.0;
  /// Door: the two jambs, in scan order (m). Corner: the far ends of its two walls.
  Eigen::Vector2d jamb_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d jamb_b = Eigen::Vector2d::Zero();
  /// How clearly the scan shows the feature, in [0, 1] (see FeatureDetector).
  double confidence = 0.0;
  /// Covariance of (x, y, theta), first-order propagation of the segments' (rho, theta)
  /// covariances (m^2, m*rad, rad^2).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// Variance of width_m (m^2); 0 for corners.
  double width_variance_m2 = 0.0;
  /// Indices of the two segments it was found from, in the detector's cascade level (the
  /// walls on both sides of a door, the two walls of a corner).
  std::uint32_t segment_a = 0;
  std::uint32_t segment_b = 0;
};

}  // namespace lidarseg
