#include <cmath>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/sim/BuildingGenerator.h"
#include "lidarseg/sim/FeatureOracle.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::sim {
namespace {
using lidarseg::kPi;

// Tests use the tuning seeds and seeds far from the held-out ones, never 101-150.
constexpr std::uint64_t kTestSeeds[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
                                        1001, 1002, 1003, 1004, 1005, 1006, 1007, 1008, 1009, 1010};

std::string worldText(const Building& b) {
  std::ostringstream os;
  writeWorldFile(os, b);
  writeTrajectoryFile(os, b);
  return os.str();
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d e = b - a;
  const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (a + t * e - p).norm();
}

TEST(BuildingGenerator, SameSeedGivesTheSameBuilding) {
  for (std::uint64_t seed : {1u, 7u, 1003u}) {
    const Building a = generateBuilding(seed), b = generateBuilding(seed);
    EXPECT_EQ(worldText(a), worldText(b)) << "seed " << seed;
    ASSERT_EQ(a.doors.size(), b.doors.size());
    for (std::size_t i = 0; i < a.doors.size(); ++i) {
      EXPECT_EQ(a.doors[i].jamb_a, b.doors[i].jamb_a);
      EXPECT_EQ(a.doors[i].kind, b.doors[i].kind);
    }
  }
}

// The generated path goes through openings only: lidarseg-simulate refuses a path through a
// wall, and the held-out evaluation runs seeds 101-150.
TEST(BuildingGenerator, ThePathGoesThroughNoWall) {
  for (std::uint64_t seed = 1; seed <= 150; ++seed) {
    const Building b = generateBuilding(seed);
    const auto c = firstWallCrossing(b.world(), b.trajectory());
    EXPECT_FALSE(c.has_value()) << "seed " << seed << " at (" << c->point.x() << ", " << c->point.y() << ")";
  }
  for (std::uint64_t seed : kTestSeeds) EXPECT_FALSE(firstWallCrossing(generateBuilding(seed).world(), generateBuilding(seed).trajectory()).has_value()) << seed;
}

TEST(BuildingGenerator, DifferentSeedsGiveDifferentBuildings) {
  std::set<std::string> texts;
  std::set<double> thicknesses, widths;
  for (std::uint64_t seed : kTestSeeds) {
    const Building b = generateBuilding(seed);
    texts.insert(worldText(b));
    thicknesses.insert(b.wall_thickness_m);
    widths.insert(b.corridor_width_m);
  }
  EXPECT_EQ(texts.size(), std::size(kTestSeeds));
  EXPECT_GT(thicknesses.size(), 20u);
  EXPECT_GT(widths.size(), 20u);
}

TEST(BuildingGenerator, DrawsStayInThePhysicalRangesAndCoverThem) {
  const BuildingParams p;
  std::size_t kinds[3] = {0, 0, 0}, doubles = 0, flush = 0, deep = 0, lobbies = 0, crosses = 0, pillars = 0;
  double min_width = 10, max_width = 0, min_corridor = 10, max_corridor = 0;
  for (std::uint64_t seed : kTestSeeds) {
    const Building b = generateBuilding(seed);
    EXPECT_GE(b.wall_thickness_m, p.wall_min_thickness_m);
    EXPECT_LE(b.wall_thickness_m, p.wall_max_thickness_m);
    EXPECT_GE(b.corridor_width_m, p.corridor_min_width_m);
    EXPECT_LE(b.corridor_width_m, p.corridor_max_width_m);
    min_corridor = std::min(min_corridor, b.corridor_width_m);
    max_corridor = std::max(max_corridor, b.corridor_width_m);
    lobbies += b.has_lobby;
    crosses += b.has_cross_corridor;
    EXPECT_GE(b.doors.size(), 8u) << "seed " << seed;
    for (const Door& d : b.doors) {
      ++kinds[static_cast<int>(d.kind)];
      EXPECT_GE(d.width(), p.single_door_min_width_m - 1e-9);
      EXPECT_LE(d.width(), p.double_door_max_width_m + 1e-9);
      min_width = std::min(min_width, d.width());
      max_width = std::max(max_width, d.width());
      doubles += d.double_leaf;
      EXPECT_DOUBLE_EQ(d.wall_thickness_m, b.wall_thickness_m);
      EXPECT_GE(d.recess_m, 0.0);
      EXPECT_LE(d.recess_m, std::min(p.max_recess_m, b.wall_thickness_m) + 1e-9);
      if (d.kind == DoorKind::kClosed) {
        flush += d.recess_m < 0.02;
        deep += d.recess_m > 0.2;
      }
      if (d.kind == DoorKind::kAjar) {
        EXPECT_GE(d.leaf_angle_rad, p.ajar_min_angle_deg * kPi / 180 - 1e-9);
        EXPECT_LE(d.leaf_angle_rad, p.ajar_max_angle_deg * kPi / 180 + 1e-9);
      }
    }
    for (const Clutter& c : b.clutter) pillars += c.pillar;
  }
  EXPECT_GT(kinds[0], 20u);  // open
  EXPECT_GT(kinds[1], 20u);  // closed
  EXPECT_GT(kinds[2], 10u);  // ajar
  EXPECT_GT(doubles, 20u);
  EXPECT_GT(flush, 3u);
  EXPECT_GT(deep, 3u);
  EXPECT_LT(min_width, 0.8);
  EXPECT_GT(max_width, 1.8);
  EXPECT_LT(min_corridor, 1.9);
  EXPECT_GT(max_corridor, 3.5);
  EXPECT_GT(lobbies, 5u);
  EXPECT_GT(crosses, 5u);
  EXPECT_GT(pillars, 5u);
}

TEST(BuildingGenerator, TrajectoryIsALoopInFreeSpace) {
  for (std::uint64_t seed : kTestSeeds) {
    const Building b = generateBuilding(seed);
    const World w = b.world();
    const Trajectory t = b.trajectory();
    EXPECT_GT(t.length(), 25.0);
    EXPECT_LT(t.length(), 120.0);
    EXPECT_EQ(b.waypoints.front(), b.waypoints.back());
    double nearest = 1e9;
    for (double s = 0; s <= t.length(); s += 0.1) {
      const Pose2D pose = t.poseAtDistance(s);
      for (const Wall& wall : w.walls()) nearest = std::min(nearest, distanceToSegment({pose.x, pose.y}, wall.a, wall.b));
    }
    EXPECT_GT(nearest, 0.35) << "seed " << seed;
  }
}

TEST(BuildingGenerator, WorldFileGivesTheSameWorld) {
  for (std::uint64_t seed : {2u, 5u, 1004u}) {
    const Building b = generateBuilding(seed);
    std::ostringstream os;
    writeWorldFile(os, b);
    std::istringstream in(os.str());
    const World read = parseWorld(in, "building.world");
    const World made = b.world();
    EXPECT_EQ(read.walls().size(), made.walls().size());
    ASSERT_EQ(read.doors().size(), made.doors().size());
    for (std::size_t i = 0; i < made.doors().size(); ++i) {
      EXPECT_LT((read.doors()[i].jamb_a - made.doors()[i].jamb_a).norm(), 1e-9);
      EXPECT_NEAR(read.doors()[i].leaf_angle_rad, made.doors()[i].leaf_angle_rad, 1e-9);
      EXPECT_EQ(read.doors()[i].double_leaf, made.doors()[i].double_leaf);
    }
    const Trajectory t = b.trajectory();
    for (double s = 0; s < t.length(); s += 2.0) {
      const Pose2D pose = t.poseAtDistance(s);
      for (int k = 0; k < 36; ++k) {
        const Eigen::Vector2d dir(std::cos(k * kPi / 18), std::sin(k * kPi / 18));
        EXPECT_NEAR(read.castRay({pose.x, pose.y}, dir), made.castRay({pose.x, pose.y}, dir), 1e-6);
      }
    }
  }
}

TEST(BuildingGenerator, DoorsAreSeenFromHeadOnToGrazingAndJambsMakeNoCorners) {
  const BeamLayout layout = BeamLayout::centred(541, 270.0 * kPi / 180.0);
  std::size_t head_on = 0, oblique = 0, beyond_60 = 0;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    const Building b = generateBuilding(seed);
    const World w = b.world();
    const FeatureOracle oracle(w);
    for (const Corner& c : oracle.corners()) {
      for (const Door& d : w.doors()) {
        EXPECT_GT((c.point - d.jamb_a).norm(), 0.2);
        EXPECT_GT((c.point - d.jamb_b).norm(), 0.2);
      }
    }
    const Trajectory t = b.trajectory();
    for (double s = 0; s < t.length(); s += 0.5) {
      for (const Feature& f : oracle.visible(t.poseAtDistance(s), layout, 20.0)) {
        if (!isDoor(f.type) || !f.resolvable || f.position.norm() > 8.0) continue;
        // Incidence: between the line of sight and the door's normal.
        const Eigen::Vector2d n(std::cos(f.theta_rad), std::sin(f.theta_rad));
        const double incidence = std::acos(std::min(1.0, std::abs(n.dot(f.position.normalized())))) * 180 / kPi;
        head_on += incidence < 30;
        oblique += incidence >= 45 && incidence < 60;
        beyond_60 += incidence >= 60 && incidence < 70;
      }
    }
  }
  EXPECT_GT(head_on, 50u);
  EXPECT_GT(oblique, 50u);
  EXPECT_GT(beyond_60, 20u);
}

TEST(BuildingGenerator, ValidateNamesTheBadKey) {
  BuildingParams p;
  p.corridor_min_width_m = 0.5;
  try {
    p.validate();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("corridor_min_width_m"), std::string::npos) << e.what();
  }
  p = BuildingParams();
  p.double_door_max_width_m = 1.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = BuildingParams();
  p.max_open_share = 1.5;
  EXPECT_THROW(generateBuilding(1, p), std::invalid_argument);
}

TEST(BuildingGenerator, TuningAndHeldOutSeedsAreDisjoint) {
  EXPECT_TRUE(isTuningSeed(1));
  EXPECT_TRUE(isTuningSeed(20));
  EXPECT_FALSE(isTuningSeed(0));
  EXPECT_FALSE(isTuningSeed(21));
  for (std::uint64_t s = kFirstHeldOutSeed; s <= kLastHeldOutSeed; ++s) EXPECT_FALSE(isTuningSeed(s));
  EXPECT_GT(kFirstHeldOutSeed, kLastTuningSeed);
}

}  // namespace
}  // namespace lidarseg::sim
