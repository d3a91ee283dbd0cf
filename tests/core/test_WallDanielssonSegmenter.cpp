#include <cmath>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/WallDanielssonSegmenter.h"

namespace lidarseg {
namespace {
using namespace lidarseg::testing;

const SegmentLevel& level0(const Segmentation& s) { return s.level(CascadeLevel::kWallDanielsson); }

Segmentation run(const Scan& scan, const WallDanielssonParams& p = {}) {
  Segmentation out;
  WallDanielssonSegmenter(p).segment(scan, out);
  return out;
}

TEST(WallDanielssonSegmenter, NoiselessStraightWallIsOneSegment) {
  sim::World world;
  world.addWall({-20, 2}, {20, 2});
  const auto sensor = makeSensor(181, 120, 0.0);
  const Segmentation s = run(simulate(world, sensor, {0, 0, kPi / 2}));
  ASSERT_EQ(level0(s).segments.size(), 1u);
  const Segment& seg = level0(s).segments[0];
  EXPECT_EQ(seg.first_beam, 0u);
  EXPECT_EQ(seg.last_beam, 180u);
  EXPECT_EQ(seg.num_points, 181u);
  EXPECT_NEAR(seg.rho_m, 2.0, 1e-9);
  EXPECT_NEAR(seg.theta_rad, 0.0, 1e-9);  // sensor frame: the wall is straight ahead
  EXPECT_EQ(level0(s).parts.size(), 1u);
}

TEST(WallDanielssonSegmenter, CornerSplitsIntoTwoSegmentsNearTheCorner) {
  // Walls y = 0 and x = 0; the sensor at (2, 2) looks at the corner.
  const auto sensor = makeSensor(361, 180, 0.0);
  const Pose2D pose{2, 2, -3 * kPi / 4};
  const Segmentation s = run(simulate(lCorner(), sensor, pose));
  ASSERT_EQ(level0(s).segments.size(), 2u);
  for (const Segment& seg : level0(s).segments) {
    const auto m = matchWall(seg, lCorner(), pose, 0.05);
    ASSERT_TRUE(m.has_value());
    // No back-stepping: a few points past the corner bias the fit slightly, no more.
    EXPECT_LT(m->angle_error_rad, 1.0 * kDeg);
  }
  // The break happens within a few beams of the corner (beam 180 looks straight at it).
  const Segment& first = level0(s).segments[0];
  EXPECT_GE(first.last_beam, 180u);
  EXPECT_LE(first.last_beam, 190u);
  EXPECT_EQ(level0(s).segments[1].first_beam, first.last_beam + 1);
}

// The single threshold: a step of height h in a wall ends the segment when h is large
// against the threshold, and not when it is small.
TEST(WallDanielssonSegmenter, ThresholdDecidesWhetherAStepBreaksTheWall) {
  const auto sensor = makeSensor(361, 120, 0.0);
  const auto stepWorld = [](double h) {
    sim::World w;
    w.addPolyline({{-8, 2}, {0, 2}, {0, 2 + h}, {8, 2 + h}});
    return w;
  };
  const Pose2D pose{0, 0, kPi / 2};
  WallDanielssonParams p;
  p.threshold_m = 0.02;
  EXPECT_EQ(level0(run(simulate(stepWorld(0.08), sensor, pose), p)).segments.size(), 2u);
  EXPECT_EQ(level0(run(simulate(stepWorld(0.01), sensor, pose), p)).segments.size(), 1u);
  p.threshold_m = 0.05;
  EXPECT_EQ(level0(run(simulate(stepWorld(0.08), sensor, pose), p)).segments.size(), 1u);
}

TEST(WallDanielssonSegmenter, RangeJumpBreaksSegments) {
  // Two walls in line of sight, 1.5 m apart in depth: the beams jump from one to the other.
  sim::World world;
  world.addWall({-5, 2}, {0, 2});
  world.addWall({0, 3.5}, {5, 3.5});
  const auto sensor = makeSensor(181, 120, 0.0);
  const Segmentation s = run(simulate(world, sensor, {0, 0, kPi / 2}));
  ASSERT_EQ(level0(s).segments.size(), 2u);
  EXPECT_NEAR(level0(s).segments[0].rho_m, 3.5, 1e-6);  // scan order: right to left
  EXPECT_NEAR(level0(s).segments[1].rho_m, 2.0, 1e-6);
}

TEST(WallDanielssonSegmenter, InvalidBeamsBreakSegmentsAndAreNotPartOfThem) {
  sim::World world;
  world.addWall({-20, 2}, {20, 2});
  const auto sensor = makeSensor(181, 120, 0.0);
  Scan scan = simulate(world, sensor, {0, 0, kPi / 2});
  scan.ranges_m[90] = std::nan("");
  scan.ranges_m[91] = -1.0;
  scan.valid.assign(scan.size(), 1);
  scan.valid[92] = 0;
  const Segmentation s = run(scan);
  ASSERT_EQ(level0(s).segments.size(), 2u);
  EXPECT_EQ(level0(s).segments[0].last_beam, 89u);
  EXPECT_EQ(level0(s).segments[1].first_beam, 93u);
  EXPECT_EQ(s.num_valid_beams, 178u);
  EXPECT_TRUE(std::isnan(s.points[91].x()));
}

TEST(WallDanielssonSegmenter, TooFewPointsMakeNoSegment) {
  sim::World world;
  world.addWall({-20, 2}, {20, 2});
  const auto sensor = makeSensor(41, 40, 0.0);
  Scan scan = simulate(world, sensor, {0, 0, kPi / 2});
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (i % 3 == 0) scan.ranges_m[i] = INFINITY;  // runs of two valid beams only
  }
  const Segmentation s = run(scan);
  EXPECT_TRUE(level0(s).segments.empty());
  WallDanielssonParams p;
  p.min_points = 2;
  EXPECT_EQ(level0(run(scan, p)).segments.size(), 13u);
}

TEST(WallDanielssonSegmenter, ReusedOutputGivesTheSameResult) {
  const auto sensor = makeSensor(541, 270, 0.012);
  const Scan a = simulate(officeScene(), sensor, {0, 1, 0.3}, 3);
  const Scan b = simulate(lCorner(), sensor, {2, 2, -2.0}, 4);
  const WallDanielssonSegmenter wd;
  Segmentation reused, fresh;
  wd.segment(a, reused);
  wd.segment(b, reused);
  wd.segment(b, fresh);
  ASSERT_EQ(reused.levels[0].segments.size(), fresh.levels[0].segments.size());
  for (std::size_t i = 0; i < fresh.levels[0].segments.size(); ++i) {
    EXPECT_EQ(reused.levels[0].segments[i].first_beam, fresh.levels[0].segments[i].first_beam);
    EXPECT_DOUBLE_EQ(reused.levels[0].segments[i].rho_m, fresh.levels[0].segments[i].rho_m);
  }
}

TEST(WallDanielssonParams, ValidateNamesTheKey) {
  const auto expectKey = [](WallDanielssonParams p, const char* key) {
    try {
      p.validate();
      ADD_FAILURE() << "no exception for " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  WallDanielssonParams p;
  p.threshold_m = 0.0;
  expectKey(p, "wd_threshold_m");
  p = {};
  p.max_range_jump_m = std::nan("");
  expectKey(p, "wd_max_range_jump_m");
  p = {};
  p.max_range_jump_ratio = -0.1;
  expectKey(p, "wd_max_range_jump_ratio");
  p = {};
  p.min_points = 1;
  expectKey(p, "wd_min_points");
  EXPECT_THROW(WallDanielssonSegmenter{p}, std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
