#include <cmath>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/sim/FeatureOracle.h"

namespace lidarseg::sim {
namespace {
using lidarseg::kPi;

int count(const std::vector<Feature>& fs, FeatureType t) {
  return static_cast<int>(std::count_if(fs.begin(), fs.end(), [&](const Feature& f) { return f.type == t; }));
}

TEST(FeatureOracle, ConcaveAndConvexCornersFromWhereTheSensorStands) {
  // An L-shaped room: five concave corners seen from inside, one convex (the inner one).
  World w;
  w.addPolygon({{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}});
  const FeatureOracle oracle(w);
  EXPECT_EQ(oracle.corners().size(), 6u);
  const auto sensor = lidarseg::testing::makeFullTurnSensor(720, 0.0, 30.0);
  const auto fs = oracle.visible({2, 2, 0.0}, *sensor.layout, 30.0);
  EXPECT_EQ(count(fs, FeatureType::kCornerConcave), 5);
  EXPECT_EQ(count(fs, FeatureType::kCornerConvex), 1);
  for (const Feature& f : fs) {
    if (f.type != FeatureType::kCornerConvex) continue;
    // The inner corner (4, 4), in the sensor frame at (2, 2) facing +x.
    EXPECT_NEAR(f.position.x(), 2.0, 1e-9);
    EXPECT_NEAR(f.position.y(), 2.0, 1e-9);
    // Its bisector points into the free space, towards the sensor's side (-135 deg).
    EXPECT_NEAR(f.theta_rad, -3 * kPi / 4, 1e-9);
  }
  // From (8, 2) the far corner (0, 10) is hidden behind the inner corner.
  const auto hidden = oracle.visible({8, 2, 0.0}, *sensor.layout, 30.0);
  EXPECT_FALSE(std::any_of(hidden.begin(), hidden.end(), [&](const Feature& f) {
    return oracle.corners()[f.id].point.isApprox(Eigen::Vector2d(0, 10));
  }));
}

TEST(FeatureOracle, DoorsInViewRangeAndSight) {
  World w;
  w.addWall({-10, 2}, {10, 2});
  w.addDoor({DoorKind::kClosed, {1, 2}, {2, 2}, 0.1, 0.0});
  w.addDoor({DoorKind::kOpen, {-3, 2}, {-2, 2}, 0.0, 0.0});
  const FeatureOracle oracle(w);
  const auto lms = lidarseg::testing::makeSensor(541, 270, 0.0, 20.0);
  const auto fs = oracle.visible({0, 0, kPi / 2}, *lms.layout, 20.0);
  ASSERT_EQ(count(fs, FeatureType::kDoorClosed), 1);
  ASSERT_EQ(count(fs, FeatureType::kDoorOpen), 1);
  for (const Feature& f : fs) {
    if (f.type != FeatureType::kDoorClosed) continue;
    // Doorway centre (1.5, 2) world = (2, -1.5) in a sensor facing +y.
    EXPECT_NEAR(f.position.x(), 2.0, 1e-9);
    EXPECT_NEAR(f.position.y(), -1.5, 1e-9);
    EXPECT_NEAR(f.width_m, 1.0, 1e-12);
  }
  // Out of range, or behind a 180-degree sensor: nothing.
  EXPECT_TRUE(oracle.visible({0, 0, kPi / 2}, *lms.layout, 1.5).empty());
  const auto front = lidarseg::testing::makeSensor(181, 180, 0.0, 20.0);
  EXPECT_EQ(count(oracle.visible({0, 0, -kPi / 2}, *front.layout, 20.0), FeatureType::kDoorClosed), 0);
}

TEST(FeatureOracle, TJunctionsMakeTwoCornersAndDoorLeavesNone) {
  World w;
  w.addWall({-5, 0}, {5, 0});
  w.addWall({0, 0}, {0, 3});  // a T: corners on both sides of the stem
  w.addDoor({DoorKind::kAjar, {2, 0}, {2.9, 0}, 0.0, 60 * 3.14159265358979 / 180});
  const FeatureOracle oracle(w);
  ASSERT_EQ(oracle.corners().size(), 2u);
  for (const Corner& c : oracle.corners()) EXPECT_TRUE(c.point.isZero(1e-12));
  // From (1, 1) only the corner between the stem and the wall's right part can be
  // resolved (both its walls in sight), from inside: concave. The other one's left wall is
  // hidden behind the stem.
  const auto sensor = lidarseg::testing::makeFullTurnSensor(720, 0.0, 30.0);
  std::vector<Feature> resolvable;
  for (const Feature& f : oracle.visible({1, 1, 0.0}, *sensor.layout, 30.0)) {
    if (f.resolvable) resolvable.push_back(f);
  }
  ASSERT_EQ(resolvable.size(), 1u);
  EXPECT_EQ(resolvable[0].type, FeatureType::kCornerConcave);
}

TEST(FeatureOracle, ResolvableNeedsBeamsOnTheWallsAndInTheGap) {
  World w;
  w.addWall({-30, 2}, {30, 2});
  w.addDoor({DoorKind::kOpen, {0.5, 2}, {1.4, 2}, 0.0, 0.0});
  const FeatureOracle oracle(w);
  const auto lms = lidarseg::testing::makeSensor(541, 270, 0.0, 30.0);
  // In front of the door: resolvable; 15 m along the wall (grazing): seen, not resolvable.
  auto front = oracle.visible({1, 0, kPi / 2}, *lms.layout, 30.0);
  ASSERT_EQ(front.size(), 1u);
  EXPECT_TRUE(front[0].resolvable);
  EXPECT_EQ(front[0].seen_as, FeatureType::kDoorOpen);
  // The wall's normal pointing away from the sensor: world +y = sensor +x here.
  EXPECT_NEAR(front[0].theta_rad, 0.0, 1e-9);
  auto grazing = oracle.visible({-14, 0, 0.0}, *lms.layout, 30.0);
  ASSERT_EQ(grazing.size(), 1u);
  EXPECT_FALSE(grazing[0].resolvable);
}

TEST(FeatureOracle, DoorAjarWithItsLeafOutOfSightIsSeenAsOpen) {
  World w;
  w.addWall({-10, 2}, {10, 2});
  w.addWall({-10, 5}, {10, 5});
  w.addDoor({DoorKind::kAjar, {-0.45, 2}, {0.45, 2}, 0.0, 45 * kPi / 180});
  const FeatureOracle oracle(w);
  const auto lms = lidarseg::testing::makeSensor(541, 270, 0.0, 30.0);
  const auto in_front = oracle.visible({0, 0, kPi / 2}, *lms.layout, 30.0);
  ASSERT_EQ(in_front.size(), 1u);
  EXPECT_EQ(in_front[0].seen_as, FeatureType::kDoorAjar);
  // From the left, the leaf (turned towards +x behind the wall) hides behind the wall.
  const auto right = oracle.visible({-4, 0, kPi / 2}, *lms.layout, 30.0);
  ASSERT_EQ(right.size(), 1u);
  EXPECT_EQ(right[0].type, FeatureType::kDoorAjar);
  EXPECT_EQ(right[0].seen_as, FeatureType::kDoorOpen);
}

}  // namespace
}  // namespace lidarseg::sim
