#include <cmath>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/sim/ScanSimulator.h"

namespace lidarseg::sim {
namespace {
using lidarseg::kPi;

TEST(World, RayCastingGivesExactRanges) {
  World w;
  w.addWall({2, -1}, {2, 1});
  EXPECT_DOUBLE_EQ(w.castRay({0, 0}, {1, 0}), 2.0);
  const Eigen::Vector2d d(std::cos(0.3), std::sin(0.3));
  EXPECT_NEAR(w.castRay({0, 0}, d), 2.0 / std::cos(0.3), 1e-12);
  EXPECT_TRUE(std::isinf(w.castRay({0, 0}, {-1, 0})));       // behind
  EXPECT_TRUE(std::isinf(w.castRay({0, 0}, {0.5, 0.866})));  // misses the end
}

TEST(World, NearestWallWins) {
  World w = lidarseg::testing::rectangleRoom(4, 2);
  w.addWall({3, -5}, {3, 5});
  EXPECT_DOUBLE_EQ(w.castRay({1, 1}, {1, 0}), 2.0);
  EXPECT_DOUBLE_EQ(w.castRay({1, 1}, {0, 1}), 1.0);
}

TEST(World, DoorInAThickWallCutsBothFacesAndAddsTheReveals) {
  // A wall 0.2 m thick: faces y = 0 and y = 0.2; a closed door recessed 0.05 m, an open one.
  World w;
  w.addWall({-5, 0}, {5, 0});
  w.addWall({-5, 0.2}, {5, 0.2});
  Door closed;
  closed.kind = DoorKind::kClosed;
  closed.jamb_a = {-3, 0};
  closed.jamb_b = {-2, 0};
  closed.recess_m = 0.05;
  closed.wall_thickness_m = 0.2;
  w.addDoor(closed);
  Door open = closed;
  open.kind = DoorKind::kOpen;
  open.jamb_a = {1, 0};
  open.jamb_b = {2.5, 0};
  w.addDoor(open);
  EXPECT_NEAR(w.castRay({-2.5, -1}, {0, 1}), 1.05, 1e-12);  // the leaf
  EXPECT_TRUE(std::isinf(w.castRay({1.75, -1}, {0, 1})));  // through both faces
  // The reveal beside the open door's jamb_b: x = 2.5 from y = 0 to 0.2.
  EXPECT_NEAR(w.castRay({1.75, 0.1}, {1, 0}), 0.75, 1e-12);
  EXPECT_NEAR(w.castRay({-2.95, 0.15}, {1, 0}), 0.95, 1e-12);  // behind the leaf, to the far reveal
}

TEST(World, DoubleAjarDoorHasTwoLeavesHingedAtTheFrame) {
  World w;
  w.addWall({-5, 0}, {5, 0});
  Door d;
  d.kind = DoorKind::kAjar;
  d.jamb_a = {-1, 0};
  d.jamb_b = {1, 0};
  d.double_leaf = true;
  d.leaf_angle_rad = kPi / 2;
  d.second_leaf_angle_rad = kPi / 2;
  d.recess_m = 0.1;
  w.addDoor(d);
  EXPECT_EQ(d.hingeA(), Eigen::Vector2d(-1, 0.1));
  // Leaves standing straight up from (-1, 0.1) and (1, 0.1), 1 m long each.
  EXPECT_NEAR(w.castRay({0, 0.5}, {-1, 0}), 1.0, 1e-9);
  EXPECT_NEAR(w.castRay({0, 0.5}, {1, 0}), 1.0, 1e-9);
  EXPECT_TRUE(std::isinf(w.castRay({0, -1}, {0, 1})));
}

TEST(ScanSimulator, NoiselessScanMatchesGeometryAndNoReturnIsMaxRange) {
  World w;
  w.addWall({-10, 2}, {10, 2});
  SensorModel m = SensorModel::lms100();
  m.range_sigma_m = 0.0;
  ScanSimulator sim(w, m, 1);
  const Scan s = sim.scan({0, 0, kPi / 2});
  ASSERT_EQ(s.size(), 541u);
  EXPECT_NEAR(s.ranges_m[270], 2.0, 1e-12);  // straight ahead
  EXPECT_NEAR(s.ranges_m[270 + 60], 2.0 / std::cos(30 * kPi / 180), 1e-12);
  EXPECT_EQ(s.ranges_m[0], m.max_range_m);  // looking backwards: no wall
  EXPECT_FALSE(s.beamValid(0));
}

TEST(ScanSimulator, SameSeedSameScanAndNoiseHasTheRequestedSigma) {
  World w;
  w.addWall({-50, 3}, {50, 3});
  SensorModel m = SensorModel::lms100();
  const Scan a = ScanSimulator(w, m, 9).scan({0, 0, kPi / 2});
  const Scan b = ScanSimulator(w, m, 9).scan({0, 0, kPi / 2});
  EXPECT_EQ(a.ranges_m, b.ranges_m);
  double sum = 0, sq = 0;
  int n = 0;
  for (int rep = 0; rep < 20; ++rep) {
    ScanSimulator sim(w, m, 100 + rep);
    const Scan s = sim.scan({0, 0, kPi / 2});
    for (std::size_t i = 200; i <= 340; ++i) {
      const double err = s.ranges_m[i] - 3.0 / std::cos(s.layout->angle(i));
      sum += err;
      sq += err * err;
      ++n;
    }
  }
  const double mean = sum / n, sigma = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4 * 0.012 / std::sqrt(n));
  EXPECT_NEAR(sigma, 0.012, 0.012 * 0.05);
}

}  // namespace
}  // namespace lidarseg::sim

namespace lidarseg::sim {
namespace {

TEST(SensorModel, ProfilesMatchTheirDataSheets) {
  const SensorModel lms = SensorModel::lms100();
  EXPECT_EQ(lms.layout->size(), 541u);
  EXPECT_NEAR(lms.layout->meanIncrement(), 0.5 * lidarseg::testing::kDeg, 1e-12);
  EXPECT_EQ(lms.max_range_m, 20.0);
  EXPECT_EQ(lms.sigmaAt(15.0), 0.012);
  const SensorModel utm = SensorModel::utm30lx();
  EXPECT_EQ(utm.layout->size(), 1081u);
  EXPECT_NEAR(utm.layout->meanIncrement(), 0.25 * lidarseg::testing::kDeg, 1e-12);
  EXPECT_EQ(utm.sigmaAt(9.9), 0.01);
  EXPECT_EQ(utm.sigmaAt(10.1), 0.03);
  EXPECT_EQ(SensorModel::sick180().layout->size(), 181u);
  // A full turn: the beams wrap around (segments may continue across the seam), and the
  // sweep lasts the whole period but one beam.
  const SensorModel rp = SensorModel::rplidar360();
  EXPECT_EQ(rp.layout->size(), 360u);
  EXPECT_TRUE(rp.layout->wrapsAround());
  EXPECT_NEAR(rp.layout->meanIncrement(), lidarseg::testing::kDeg, 1e-12);
  EXPECT_EQ(rp.sigmaAt(3.9), 0.02);
  EXPECT_EQ(rp.sigmaAt(4.1), 0.05);
  EXPECT_NEAR(ScanSimulator(World{}, rp, 1).sweepDuration(), 359.0 / 360.0 / 5.5, 1e-12);
  EXPECT_FALSE(SensorModel::lms100().layout->wrapsAround());
}

}  // namespace
}  // namespace lidarseg::sim
