#include <cmath>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::sim {
namespace {
using lidarseg::kPi;
const std::string kWorlds = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";

// A path wholly inside a pillar or a box crosses no outline: the point inside clutter is
// found by parity (it was simulated from inside a solid pillar, issue 16); a point outside
// all clutter, or inside a room's walls, is free.
TEST(Trajectory, ThePointInsideClutterIsFound) {
  World w;
  w.addPolygon({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, SurfaceKind::kWall);  // a room
  w.addPolygon({{1, 1}, {2, 1}, {2, 2}, {1, 2}}, SurfaceKind::kClutter);  // a pillar in it
  const auto inside = clutterHolding(w, {1.5, 1.5});
  ASSERT_TRUE(inside.has_value());
  EXPECT_EQ(w.walls()[*inside].kind, SurfaceKind::kClutter);
  EXPECT_NEAR(w.walls()[*inside].a.x(), 2.0, 1e-12);  // the nearest side along +x
  EXPECT_FALSE(clutterHolding(w, {3.0, 3.0}).has_value()) << "in the room, beside the pillar";
  EXPECT_FALSE(clutterHolding(w, {0.5, 1.0}).has_value()) << "level with a corner, outside";
  EXPECT_FALSE(clutterHolding(w, {3.0, 1.5}).has_value()) << "right of the pillar";
}

// The first wall a path goes through: on a straight leg, on a rounded corner's arc, a door
// leaf; none through an opening or beside a wall; and the project's own worlds are clear.
TEST(Trajectory, TheFirstWallCrossedIsFoundOnLegsAndArcs) {
  World w;
  w.addWall({5, -1}, {5, 1});  // across the first leg
  const Trajectory straight({{0, 0}, {10, 0}}, 1.0, 0.5);
  auto c = firstWallCrossing(w, straight);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->s_m, 5.0, 1e-9);
  EXPECT_NEAR(c->point.x(), 5.0, 1e-9);
  EXPECT_EQ(c->wall, 0u);
  EXPECT_EQ(straight.legAtDistance(c->s_m), 0u);
  // An opening in that wall lets the path through.
  World open;
  open.addWall({5, -1}, {5, -0.4});
  open.addWall({5, 0.4}, {5, 1});
  EXPECT_FALSE(firstWallCrossing(open, straight).has_value());
  // The rounded corner (radius 1 m at (10, 0): the arc from (9, 0) to (10, 1) about (9, 1))
  // crosses a short wall inside the corner, on the leg it leaves; it passes inside one that
  // cuts the corner's tip, which the waypoints' polyline would cross.
  const Trajectory turn({{0, 0}, {10, 0}, {10, 10}}, 1.0, 1.0);
  World diagonal;  // on x + y = 9.5: the arc meets it at (9.41, 0.09)
  diagonal.addWall({9.0, 0.5}, {9.5, 0.0});
  ASSERT_TRUE(firstWallCrossing(diagonal, turn).has_value());
  EXPECT_EQ(turn.legAtDistance(firstWallCrossing(diagonal, turn)->s_m), 0u);
  World beside;  // on x + y = 10.2 across the tip: the arc meets that line at x = 9.8, off the wall
  beside.addWall({9.9, 0.3}, {10.3, -0.1});
  EXPECT_FALSE(firstWallCrossing(beside, turn).has_value());
  // The arc's chords stay within 1 mm of it.
  const auto poly = turn.polyline(1e-3);
  for (std::size_t k = 0; k + 1 < poly.size(); ++k) {
    const Pose2D mid = turn.poseAtDistance(0.5 * (poly[k].first + poly[k + 1].first));
    const Eigen::Vector2d chord_mid = 0.5 * (poly[k].second + poly[k + 1].second);
    EXPECT_LT((chord_mid - Eigen::Vector2d(mid.x, mid.y)).norm(), 1.0e-3 + 1e-9) << k;
  }
  // A closed door's leaf is a wall to the robot.
  World door_world;
  door_world.addWall({5, -2}, {5, 2});
  Door d;
  d.jamb_a = {5, -0.45};
  d.jamb_b = {5, 0.45};
  d.kind = DoorKind::kClosed;
  d.recess_m = 0.05;
  door_world.addDoor(d);
  c = firstWallCrossing(door_world, straight);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(door_world.walls()[c->wall].kind, SurfaceKind::kDoor);
  d.kind = DoorKind::kOpen;
  World open_door;
  open_door.addWall({5, -2}, {5, 2});
  open_door.addDoor(d);
  EXPECT_FALSE(firstWallCrossing(open_door, straight).has_value());
  // The committed worlds and their trajectories.
  for (const char* name : {"maze", "hospital"}) {
    EXPECT_FALSE(firstWallCrossing(loadWorldFile(kWorlds + name + ".world"),
                                   loadTrajectoryFile(kWorlds + name + ".traj")).has_value())
        << name;
  }
}

TEST(Trajectory, StraightLegsAndRoundedCorner) {
  const Trajectory t({{0, 0}, {10, 0}, {10, 10}}, 2.0, 1.0);
  // Two legs of 10 m minus 1 m each, plus a quarter circle of radius 1.
  EXPECT_NEAR(t.length(), 18.0 + kPi / 2, 1e-12);
  EXPECT_NEAR(t.duration(), t.length() / 2.0, 1e-12);
  const Pose2D mid_leg = t.poseAt(2.5);
  EXPECT_NEAR(mid_leg.x, 5.0, 1e-12);
  EXPECT_NEAR(mid_leg.yaw, 0.0, 1e-12);
  // Middle of the arc: centre (9, 1), radius 1, heading 45 deg.
  const Pose2D arc = t.poseAtDistance(9.0 + kPi / 4);
  EXPECT_NEAR(arc.x, 9.0 + std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(arc.y, 1.0 - std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(arc.yaw, kPi / 4, 1e-12);
  const Pose2D end = t.poseAt(1e9);
  EXPECT_NEAR(end.x, 10.0, 1e-12);
  EXPECT_NEAR(end.y, 10.0, 1e-12);
  EXPECT_NEAR(end.yaw, kPi / 2, 1e-12);
}

TEST(Trajectory, PoseIsContinuous) {
  const Trajectory t({{0, 0}, {5, 0}, {5, 3}, {-2, 3}, {-2, -4}}, 1.0, 0.8);
  Pose2D prev = t.poseAtDistance(0.0);
  for (double s = 0.01; s <= t.length(); s += 0.01) {
    const Pose2D p = t.poseAtDistance(s);
    EXPECT_NEAR(std::hypot(p.x - prev.x, p.y - prev.y), 0.01, 1e-6) << "s = " << s;
    EXPECT_LT(std::abs(std::remainder(p.yaw - prev.yaw, 2 * kPi)), 0.01 / 0.8 + 1e-9);
    prev = p;
  }
}

// The shipped trajectories start and end at the origin, are about 110 m long like the
// paper's, and never come closer than 0.5 m to a wall.
TEST(Trajectory, ShippedTrajectoriesLoopInFreeSpace) {
  for (const char* name : {"maze", "hospital"}) {
    const World world = loadWorldFile(kWorlds + name + ".world");
    const Trajectory t = loadTrajectoryFile(kWorlds + name + ".traj");
    EXPECT_NEAR(t.length(), 108.0, 3.0) << name;
    const Pose2D start = t.poseAt(0), end = t.poseAt(t.duration());
    EXPECT_NEAR(std::hypot(start.x, start.y), 0.0, 1e-9) << name;
    EXPECT_NEAR(std::hypot(end.x, end.y), 0.0, 1e-9) << name;
    const RayCaster caster(world);
    for (double s = 0.0; s <= t.length(); s += 0.25) {
      const Pose2D p = t.poseAtDistance(s);
      for (int k = 0; k < 16; ++k) {
        const double a = k * kPi / 8;
        EXPECT_GT(caster.cast({p.x, p.y}, {std::cos(a), std::sin(a)}).range, 0.5)
            << name << " at s = " << s;
      }
    }
  }
}

TEST(Trajectory, FileErrorsNameTheLine) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/bad.traj";
  const auto errorOf = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      loadTrajectoryFile(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_EQ(errorOf("speed 1\nwaypoint 0 0\nwaypont 1 1\n"),
            path + ":3: unknown keyword 'waypont' (speed, turn_radius, waypoint)");
  EXPECT_EQ(errorOf("waypoint 0\n"), path + ":1: 'waypoint' expects 2 numbers, got 1");
  EXPECT_EQ(errorOf("speed -1\n"), path + ":1: speed must be > 0");
  EXPECT_EQ(errorOf("waypoint 0 0\nwaypoint 0 0\n"), path + ":2: waypoint equal to the previous one");
  EXPECT_EQ(errorOf("waypoint 0 0\n"), path + ": needs at least 2 waypoints");
  // A reliability attack's findings: a path that turns back on itself (the robot turned at
  // x = 0.5 and its heading flipped between two scans), and a second speed that replaced the
  // first for the whole path.
  EXPECT_EQ(errorOf("waypoint 0 0\nwaypoint 1 0\nwaypoint 0 0\n"),
            path + ":3: the path turns back by 180 deg at the waypoint before this one (at most 170 deg can be "
                   "driven): add waypoints to turn around");
  EXPECT_EQ(errorOf("waypoint 0 0\nwaypoint 1 0\nwaypoint 1 1\nwaypoint 0 1\n"), "no exception");
  EXPECT_EQ(errorOf("speed 1\nwaypoint 0 0\nspeed 2\nwaypoint 1 0\n"),
            path + ":3: 'speed' given twice (first at line 1): one value holds for the whole path");
  EXPECT_EQ(errorOf("turn_radius 0.5\nturn_radius 0.2\nwaypoint 0 0\nwaypoint 1 0\n"),
            path + ":2: 'turn_radius' given twice (first at line 1): one value holds for the whole path");
}

}  // namespace
}  // namespace lidarseg::sim
