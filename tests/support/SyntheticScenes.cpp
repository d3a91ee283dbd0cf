#include "SyntheticScenes.h"

#include <cmath>
#include <memory>

namespace lidarseg::testing {

sim::SensorModel makeSensor(std::size_t num_beams, double fov_deg, double sigma_m,
                            double max_range_m) {
  sim::SensorModel m;
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(num_beams, fov_deg * kDeg));
  m.max_range_m = max_range_m;
  m.min_range_m = 0.05;
  m.range_sigma_m = sigma_m;
  return m;
}

sim::SensorModel makeFullTurnSensor(std::size_t num_beams, double sigma_m, double max_range_m) {
  sim::SensorModel m;
  m.layout = std::make_shared<BeamLayout>(
      BeamLayout::uniform(num_beams, -kPi, 2.0 * kPi / static_cast<double>(num_beams)));
  m.max_range_m = max_range_m;
  m.min_range_m = 0.05;
  m.range_sigma_m = sigma_m;
  return m;
}

sim::World rectangleRoom(double w, double h) {
  sim::World world;
  world.addPolygon({{0, 0}, {w, 0}, {w, h}, {0, h}});
  return world;
}

sim::World lCorner() {
  sim::World world;
  world.addPolyline({{5, 0}, {0, 0}, {0, 5}});
  return world;
}

sim::World corridorWithDoors(double width, const std::vector<RecessedDoor>& doors) {
  sim::World world;
  world.addWall({-10, 0}, {20, 0});
  double x = -10.0;
  for (const RecessedDoor& d : doors) {
    const double top = width + d.depth;
    world.addPolyline({{x, width},
                       {d.x_min, width},
                       {d.x_min, top},
                       {d.x_min + d.width, top},
                       {d.x_min + d.width, width}});
    x = d.x_min + d.width;
  }
  world.addWall({x, width}, {20, width});
  return world;
}

sim::World wallWithBox(double box_x, double box_side) {
  sim::World world;
  world.addWall({-5, 2}, {5, 2});
  const double l = box_x - 0.5 * box_side, r = box_x + 0.5 * box_side;
  world.addPolyline({{l, 2}, {l, 2 - box_side}, {r, 2 - box_side}, {r, 2}});
  return world;
}

sim::World officeScene() {
  sim::World world;
  // Corridor 2 m wide along x with recessed doors above and openings below.
  world.addPolyline({{-12, 2}, {-6, 2}, {-6, 2.1}, {-5.1, 2.1}, {-5.1, 2}, {-1, 2}, {-1, 2.15},
                     {-0.1, 2.15}, {-0.1, 2}, {4, 2}, {4, 2.05}, {4.9, 2.05}, {4.9, 2}, {12, 2}});
  world.addPolyline({{-12, 0}, {-3, 0}});
  world.addPolyline({{-2, 0}, {2.5, 0}});
  world.addPolyline({{3.5, 0}, {12, 0}});
  // A room below the corridor, seen through the openings.
  world.addPolyline({{-3, 0}, {-3, -4}, {3.5, -4}, {3.5, 0}});
  world.addPolygon({{-1.0, -2.5}, {-0.6, -2.5}, {-0.6, -2.1}, {-1.0, -2.1}});  // pillar
  // Clutter against the walls: a bin and a cabinet.
  world.addPolyline({{1.0, 2}, {1.0, 1.7}, {1.3, 1.7}, {1.3, 2}});
  world.addPolyline({{6.0, 0}, {6.0, 0.4}, {7.0, 0.4}, {7.0, 0}});
  // Corridor ends.
  world.addWall({-12, 0}, {-12, 2});
  world.addWall({12, 0}, {12, 2});
  return world;
}

Scan simulate(const sim::World& world, const sim::SensorModel& sensor, const Pose2D& pose,
              std::uint64_t seed) {
  sim::ScanSimulator simulator(world, sensor, seed);
  return simulator.scan(pose);
}

Eigen::Vector2d toWorld(const Pose2D& pose, const Eigen::Vector2d& p) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  return {pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y()};
}

std::optional<WallMatch> matchWall(const Segment& segment, const sim::World& world,
                                   const Pose2D& pose, double max_distance_m) {
  const Eigen::Vector2d a = toWorld(pose, segment.start);
  const Eigen::Vector2d b = toWorld(pose, segment.end);
  std::optional<WallMatch> best;
  for (std::size_t i = 0; i < world.walls().size(); ++i) {
    const sim::Wall& w = world.walls()[i];
    const Eigen::Vector2d d = (w.b - w.a).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    const double dist = std::max(std::abs(n.dot(a - w.a)), std::abs(n.dot(b - w.a)));
    if (dist > max_distance_m) continue;
    // The segment must overlap the wall along its direction, not merely share its line.
    const double ta = d.dot(a - w.a), tb = d.dot(b - w.a), len = (w.b - w.a).norm();
    if (std::max(ta, tb) < -0.05 || std::min(ta, tb) > len + 0.05) continue;
    const Eigen::Vector2d sd = (b - a).normalized();
    const double angle = std::acos(std::min(1.0, std::abs(sd.dot(d))));
    if (!best || dist < best->endpoint_distance_m) best = WallMatch{i, dist, angle};
  }
  return best;
}

}  // namespace lidarseg::testing
