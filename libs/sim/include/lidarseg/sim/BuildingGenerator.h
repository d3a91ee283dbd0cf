#pragma once
/// @file BuildingGenerator.h
/// Procedural building floors from a seed: corridors, rooms, lobbies, pillars, clutter and
/// doors of every kind, with a trajectory through the corridors past the doors (issue 18).
/// Buildings the detector was not tuned on: tune on seeds kTuningSeeds, measure on
/// kHeldOutSeeds only.

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Seeds of the buildings the detector's rules may be tuned on (inclusive).
constexpr std::uint64_t kFirstTuningSeed = 1;
constexpr std::uint64_t kLastTuningSeed = 20;
/// Seeds of the held-out buildings: measured on, never tuned on (inclusive).
constexpr std::uint64_t kFirstHeldOutSeed = 101;
constexpr std::uint64_t kLastHeldOutSeed = 150;

/// Whether a seed may be used while tuning (seeds >= kFirstHeldOutSeed never may).
constexpr bool isTuningSeed(std::uint64_t seed) { return seed >= kFirstTuningSeed && seed <= kLastTuningSeed; }

/// The ranges a building's dimensions are drawn from (uniformly). Lengths in metres,
/// angles in degrees, probabilities in [0, 1], densities per metre of corridor wall. The
/// defaults are the physical ranges of issue 18: doors 0.7–2.0 m (single and double),
/// recesses from flush to 0.3 m, walls 0.1–0.3 m thick, corridors 1.5–4 m wide.
struct BuildingParams {
  /// Corridor width, one per building (m).
  double corridor_min_width_m = 1.5;
  double corridor_max_width_m = 4.0;
  /// Wall thickness, one per building (m): the gap between two free spaces' faces.
  double wall_min_thickness_m = 0.1;
  double wall_max_thickness_m = 0.3;
  /// Single doors' and double doors' widths, jamb to jamb, per door (m).
  double single_door_min_width_m = 0.7;
  double single_door_max_width_m = 1.2;
  double double_door_min_width_m = 1.2;
  double double_door_max_width_m = 2.0;
  /// Share of double doors, per building drawn in [0, this].
  double max_double_door_share = 0.5;
  /// A closed door's leaf (an ajar door's hinges) lies in [0, min(max_recess_m, wall
  /// thickness)] behind the corridor's wall face, per door (m): 0 is flush.
  double max_recess_m = 0.3;
  /// Shares of open and ajar doors, per building drawn in [0, these]; the rest are closed.
  double max_open_share = 0.45;
  double max_ajar_share = 0.3;
  /// Opening angle of an ajar door's leaf, per leaf (deg).
  double ajar_min_angle_deg = 15.0;
  double ajar_max_angle_deg = 75.0;
  /// Rooms: width along the corridor and depth away from it, per room (m).
  double room_min_width_m = 3.0;
  double room_max_width_m = 6.0;
  double room_min_depth_m = 3.0;
  double room_max_depth_m = 6.0;
  /// Length of the block of rooms the ring of corridors goes around (m).
  double block_min_length_m = 14.0;
  double block_max_length_m = 24.0;
  /// Probability of a corridor across the block (T junctions, doors in its side walls);
  /// the trajectory then drives the smaller loop through it.
  double cross_corridor_probability = 0.5;
  /// Probability of a lobby beside a corridor, and its size (m).
  double lobby_probability = 0.7;
  double lobby_min_width_m = 5.0;
  double lobby_max_width_m = 9.0;
  double lobby_min_depth_m = 3.0;
  double lobby_max_depth_m = 6.0;
  /// Square pillars in a lobby: at most this many, side in [min, max] (m).
  std::size_t max_pillars = 4;
  double pillar_min_size_m = 0.3;
  double pillar_max_size_m = 0.6;
  /// Clutter against the corridors' walls (cabinets, bins), per building drawn in
  /// [0, max_clutter_per_m] items per metre of wall; at most this deep (m).
  double max_clutter_per_m = 0.15;
  double clutter_max_depth_m = 0.6;
  /// Probability of a box against the back wall of a room.
  double room_clutter_probability = 0.5;
  /// Wall kept free on each side of a door, and between clutter and a door (m): more than
  /// the 0.5 m of wall the ground truth needs beside a jamb (FeatureOracleParams).
  double door_margin_m = 0.6;
  /// Exits: closed doors in the outer walls at the ring's two ends, at most this many.
  std::size_t max_exits = 2;
  /// The trajectory keeps this far from walls and clutter (m), drives at this speed and
  /// rounds its corners with this radius.
  double path_clearance_m = 0.5;
  double speed_mps = 1.0;
  double turn_radius_m = 0.6;

  /// @throws std::invalid_argument naming the first bad key and its value.
  void validate() const;
};

/// A rectangle of clutter (cabinet, bin) or a square pillar, world frame (m, rad).
struct Clutter {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double width_m = 0.0;  ///< along yaw
  double depth_m = 0.0;  ///< across yaw
  double yaw_rad = 0.0;
  bool pillar = false;
};

/// A generated building floor, world frame (m). Frames: x along the block of rooms, y
/// across; the block's bottom-left room corner at the origin.
struct Building {
  std::uint64_t seed = 0;
  /// Drawn for this building.
  double wall_thickness_m = 0.0;
  double corridor_width_m = 0.0;
  double open_share = 0.0;
  double ajar_share = 0.0;
  double double_door_share = 0.0;
  double clutter_per_m = 0.0;
  bool has_cross_corridor = false;
  bool has_lobby = false;
  /// The faces of the walls (the boundary of the free space), before the doors cut them.
  std::vector<Wall> walls;
  std::vector<Clutter> clutter;
  /// Every door; wall_thickness_m set, recess_m the leaf's (closed) or hinges' (ajar) depth.
  std::vector<Door> doors;
  /// A closed loop through the corridors (first == last), driven at speed_mps.
  std::vector<Eigen::Vector2d> waypoints;
  double speed_mps = 1.0;
  double turn_radius_m = 0.6;

  /// The walls, the clutter and the doors (applied last, as loadWorldFile does).
  World world() const;
  Trajectory trajectory() const;
};

/// The building of that seed; the same seed and parameters give the same building on
/// every platform (std::mt19937_64 and the generator's own uniform draws). O(rooms^2).
/// @throws std::invalid_argument for invalid parameters.
Building generateBuilding(std::uint64_t seed, const BuildingParams& params = {});

/// The building as a world file (config/worlds/README.md): loadWorldFile() of it gives the
/// same world (coordinates in mm, angles in 0.1 deg, as generated).
void writeWorldFile(std::ostream& os, const Building& building);
/// The trajectory as a trajectory file (loadTrajectoryFile()).
void writeTrajectoryFile(std::ostream& os, const Building& building);
/// One line per door: `id,kind,width,double,recess,thickness,leaf_deg,second_leaf_deg,x,y`
/// (id as in World::doors() and the simulator's features.csv; m and deg).
void writeDoorTable(std::ostream& os, const Building& building);

}  // namespace lidarseg::sim
