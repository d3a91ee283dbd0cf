#pragma once
// Synthetic scenes with known geometry, shared by the tests and the benchmarks.

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/core/Segmentation.h"
#include "lidarseg/sim/ScanSimulator.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::testing {

inline constexpr double kDeg = kPi / 180.0;

/// A sensor with `num_beams` beams over `fov_deg` degrees centred on x, noise sigma.
sim::SensorModel makeSensor(std::size_t num_beams, double fov_deg, double sigma_m,
                            double max_range_m = 20.0);
/// A 360-degree sensor: beams from -180 deg, one every 360/num_beams degrees.
sim::SensorModel makeFullTurnSensor(std::size_t num_beams, double sigma_m,
                                    double max_range_m = 20.0);

/// Axis-aligned rectangular room [0, w] x [0, h].
sim::World rectangleRoom(double w, double h);
/// Two walls meeting at a right angle at the origin: along +x and along +y, 5 m long.
sim::World lCorner();

/// A door recessed into the upper wall of a corridor.
struct RecessedDoor {
  double x_min = 0.0;   ///< left jamb (m)
  double width = 0.9;   ///< m
  double depth = 0.1;   ///< recess behind the wall line (m)
};
/// Corridor between y = 0 and y = width, from x = -10 to x = 20, with doors recessed
/// into the upper wall (y = width).
sim::World corridorWithDoors(double width, const std::vector<RecessedDoor>& doors);

/// A straight wall y = 2 from x = -5 to 5, with a square box of side `box_side` standing
/// against it, centred at x = box_x.
sim::World wallWithBox(double box_x, double box_side);

/// A building-like scene: corridor with doors (open and recessed), a side room, pillars
/// and clutter; used by the benchmarks as a typical indoor scan.
sim::World officeScene();

/// Simulates one scan.
Scan simulate(const sim::World& world, const sim::SensorModel& sensor, const Pose2D& pose,
              std::uint64_t seed = 1);

/// How a segment lies against the true walls (sensor-frame segment, world-frame walls).
struct WallMatch {
  std::size_t wall = 0;
  /// Largest distance of the segment's endpoints from the wall's line (m).
  double endpoint_distance_m = 0.0;
  /// Angle between segment and wall (rad, in [0, pi/2]).
  double angle_error_rad = 0.0;
};
/// The wall that best explains `segment` seen from `pose`, if any wall's line passes within
/// `max_distance_m` of both endpoints.
std::optional<WallMatch> matchWall(const Segment& segment, const sim::World& world,
                                   const Pose2D& pose, double max_distance_m);

/// Sensor-frame point to world frame.
Eigen::Vector2d toWorld(const Pose2D& pose, const Eigen::Vector2d& p);

}  // namespace lidarseg::testing
