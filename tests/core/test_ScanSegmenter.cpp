// The whole pipeline (W-D + cascade) on synthetic scenes with known geometry, noise sweeps,
// level invariants and bad input.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/ScanSegmenter.h"

namespace lidarseg {
namespace {
using namespace lidarseg::testing;

const std::vector<Segment>& segmentsAt(const Segmentation& s, CascadeLevel l) {
  return s.level(l).segments;
}

// The parameters a user would set for a sensor with this range noise: the noise model,
// and a Wall-Danielsson threshold of at least 1.5 sigma (config/default.ini says so).
SegmentationParams paramsForNoise(double sigma) {
  SegmentationParams p;
  p.noise.range_sigma_m = std::max(sigma, 1e-3);
  p.wall_danielsson.threshold_m = std::max(p.wall_danielsson.threshold_m, 1.5 * sigma);
  return p;
}

// Checks the structural invariants of a segmentation.
void expectInvariants(const Segmentation& s) {
  double previous_longest = 0.0;
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    const auto level = static_cast<CascadeLevel>(l);
    const auto& segs = segmentsAt(s, level);
    if (l > 0) {
      EXPECT_LE(segs.size(), s.levels[l - 1].segments.size()) << toString(level);
    }
    double longest = 0.0;
    for (std::size_t i = 0; i < segs.size(); ++i) {
      longest = std::max(longest, segs[i].length_m);
      EXPECT_EQ(s.pointsOf(level, i).size(), segs[i].num_points) << toString(level);
      EXPECT_GE(segs[i].rho_m, 0.0);
      EXPECT_TRUE(segs[i].covariance.allFinite());
    }
    // Fusion never shortens the longest segment; erosion keeps it unless it removes all.
    if (!segs.empty()) {
      EXPECT_GE(longest, previous_longest - 1e-9) << toString(level);
    }
    if (l != static_cast<std::size_t>(CascadeLevel::kEroded) || !segs.empty()) {
      previous_longest = std::max(previous_longest, longest);
    }
  }
}

// --- Noise sweep on a room seen by a 360-degree sensor (the back wall crosses the
// wrap-around of the scan) ------------------------------------------------------------
class RoomNoiseSweep : public ::testing::TestWithParam<double> {};

TEST_P(RoomNoiseSweep, FourWallsAtLevel3WithSmallErrors) {
  const double sigma = GetParam();
  const sim::World room = rectangleRoom(6, 4);
  const Pose2D pose{2.6, 1.7, 0.2};
  const auto sensor = makeFullTurnSensor(720, sigma);
  const ScanSegmenter segmenter(paramsForNoise(sigma));
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Segmentation s = segmenter.process(simulate(room, sensor, pose, seed));
    expectInvariants(s);
    const auto& top = segmentsAt(s, CascadeLevel::kFusedAgain);
    ASSERT_EQ(top.size(), 4u) << "sigma " << sigma << " seed " << seed;
    std::vector<bool> seen(4, false);
    for (const Segment& seg : top) {
      const auto m = matchWall(seg, room, pose, 0.03 + 2 * sigma);
      ASSERT_TRUE(m.has_value()) << "sigma " << sigma;
      EXPECT_LT(m->angle_error_rad, 1.0 * kDeg) << "sigma " << sigma;
      seen[m->wall] = true;
      EXPECT_GT(seg.length_m, 3.0);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 4);
    // The wall behind the sensor is one segment across the wrap-around.
    const auto wrapped = std::count_if(top.begin(), top.end(),
                                       [](const Segment& g) { return g.first_beam > g.last_beam; });
    EXPECT_EQ(wrapped, 1);
  }
}

INSTANTIATE_TEST_SUITE_P(RangeNoise, RoomNoiseSweep,
                         ::testing::Values(0.0, 0.005, 0.012, 0.02, 0.03),
                         [](const ::testing::TestParamInfo<double>& p) {
                           return "sigma_" + std::to_string(static_cast<int>(p.param * 1000)) + "mm";
                         });

// --- L corner with a 270-degree LMS100-like sensor -------------------------------------
class CornerNoiseSweep : public ::testing::TestWithParam<double> {};

TEST_P(CornerNoiseSweep, TwoSegmentsMeetingAtTheCorner) {
  const double sigma = GetParam();
  const Pose2D pose{1.5, 2.0, -2.3};
  const ScanSegmenter segmenter(paramsForNoise(sigma));
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Segmentation s =
        segmenter.process(simulate(lCorner(), makeSensor(541, 270, sigma), pose, seed));
    expectInvariants(s);
    const auto& top = segmentsAt(s, CascadeLevel::kFusedAgain);
    ASSERT_EQ(top.size(), 2u) << "sigma " << sigma << " seed " << seed;
    // Intersection of the two fitted lines against the true corner (world origin).
    Eigen::Matrix2d a;
    a << std::cos(top[0].theta_rad), std::sin(top[0].theta_rad), std::cos(top[1].theta_rad),
        std::sin(top[1].theta_rad);
    const Eigen::Vector2d corner = toWorld(pose, a.inverse() * Eigen::Vector2d(top[0].rho_m, top[1].rho_m));
    EXPECT_LT(corner.norm(), 0.01 + sigma) << "sigma " << sigma;
    for (const Segment& seg : top) {
      const auto m = matchWall(seg, lCorner(), pose, 0.03 + 2 * sigma);
      ASSERT_TRUE(m.has_value());
      EXPECT_LT(m->angle_error_rad, 0.5 * kDeg);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RangeNoise, CornerNoiseSweep, ::testing::Values(0.0, 0.012, 0.03));

// --- Corridor with doors recessed 5 to 20 cm -------------------------------------------
// The sensor faces the door wall: the middle door is seen head-on, the outer two at about
// 63 degrees of incidence. A 5 cm recess at a grazing angle in LMS100 noise is the paper's
// stated limit ("doors with small shift"): there the test only requires the doors seen
// below `max_incidence_deg`, and records how many of the others were found.
struct DoorCase {
  double depth;
  double sigma;
  double max_incidence_deg;
};
class RecessedDoors : public ::testing::TestWithParam<DoorCase> {};

TEST_P(RecessedDoors, DoorSegmentSurvivesAtLevels0And1) {
  const DoorCase c = GetParam();
  const std::vector<RecessedDoor> doors{{3.0, 0.9, c.depth}, {5.5, 0.9, c.depth}, {8.0, 0.9, c.depth}};
  const sim::World world = corridorWithDoors(2.0, doors);
  const Pose2D pose{5.9, 0.8, kPi / 2};
  const ScanSegmenter segmenter(paramsForNoise(c.sigma));
  int required = 0, found_required = 0, optional = 0, found_optional = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Segmentation s =
        segmenter.process(simulate(world, makeSensor(541, 270, c.sigma), pose, seed));
    expectInvariants(s);
    for (CascadeLevel level : {CascadeLevel::kWallDanielsson, CascadeLevel::kFused}) {
      for (const RecessedDoor& d : doors) {
        // Segments on the door's line, inside its jambs, covering most of its visible part
        // (the near jamb hides depth * tan(incidence)). Level 0 may hold the door in a few
        // pieces (noise breaks); level 1 must have fused them into one.
        const double incidence = std::atan2(std::abs(d.x_min + 0.5 * d.width - pose.x), 2.0 - pose.y);
        const double visible = d.width - d.depth * std::tan(incidence);
        double covered = 0.0, longest = 0.0;
        for (const Segment& g : segmentsAt(s, level)) {
          const Eigen::Vector2d a = toWorld(pose, g.start), b = toWorld(pose, g.end);
          const double y_line = 2.0 + d.depth;
          if (std::abs(a.y() - y_line) < 0.02 + c.sigma && std::abs(b.y() - y_line) < 0.02 + c.sigma &&
              std::min(a.x(), b.x()) > d.x_min - 0.05 &&
              std::max(a.x(), b.x()) < d.x_min + d.width + 0.05) {
            covered += g.length_m;
            longest = std::max(longest, g.length_m);
          }
        }
        const bool found = level == CascadeLevel::kWallDanielsson ? covered > 0.6 * visible
                                                                  : longest > 0.6 * visible;
        const double incidence_deg = incidence / kDeg;
        if (incidence_deg <= c.max_incidence_deg) {
          ++required;
          found_required += found;
          EXPECT_TRUE(found) << "door at x=" << d.x_min << " (incidence " << incidence_deg
                             << " deg) depth " << d.depth << " sigma " << c.sigma << " level "
                             << toString(level) << " seed " << seed;
        } else {
          ++optional;
          found_optional += found;
        }
      }
    }
  }
  EXPECT_GT(required, 0);
  RecordProperty("found_beyond_max_incidence",
                 std::to_string(found_optional) + "/" + std::to_string(optional));
}

INSTANTIATE_TEST_SUITE_P(DepthAndNoise, RecessedDoors,
                         ::testing::Values(DoorCase{0.05, 0.0, 90}, DoorCase{0.05, 0.005, 45},
                                           DoorCase{0.05, 0.012, 45}, DoorCase{0.10, 0.012, 90},
                                           DoorCase{0.20, 0.012, 90}, DoorCase{0.20, 0.03, 45}),
                         [](const ::testing::TestParamInfo<DoorCase>& p) {
                           return "depth_" + std::to_string(static_cast<int>(p.param.depth * 100)) +
                                  "cm_sigma_" + std::to_string(static_cast<int>(p.param.sigma * 1000)) +
                                  "mm_required_below_" +
                                  std::to_string(static_cast<int>(p.param.max_incidence_deg)) + "deg";
                         });

// --- A small box against a wall: the two sides of the wall fuse at level 3 -------------
TEST(ScanSegmenter, WallSidesAroundASmallBoxFuseAtLevel3) {
  const double box_x = 0.6, side = 0.15;
  const sim::World world = wallWithBox(box_x, side);
  const Pose2D pose{0, 0, kPi / 2};
  const ScanSegmenter segmenter;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Segmentation s = segmenter.process(simulate(world, makeSensor(541, 270, 0.012), pose, seed));
    expectInvariants(s);
    const auto onWall = [&](const Segment& g) {
      return std::abs(toWorld(pose, g.start).y() - 2.0) < 0.03 &&
             std::abs(toWorld(pose, g.end).y() - 2.0) < 0.03;
    };
    const auto spansBox = [&](const Segment& g) {
      const double xa = toWorld(pose, g.start).x(), xb = toWorld(pose, g.end).x();
      return std::min(xa, xb) < box_x - side && std::max(xa, xb) > box_x + side;
    };
    const auto& fused = segmentsAt(s, CascadeLevel::kFused);
    EXPECT_GE(std::count_if(fused.begin(), fused.end(), onWall), 2) << "seed " << seed;
    EXPECT_FALSE(std::any_of(fused.begin(), fused.end(), [&](const Segment& g) {
      return onWall(g) && spansBox(g);
    }));
    const auto& top = segmentsAt(s, CascadeLevel::kFusedAgain);
    EXPECT_EQ(std::count_if(top.begin(), top.end(), onWall), 1) << "seed " << seed;
    EXPECT_TRUE(std::any_of(top.begin(), top.end(), [&](const Segment& g) {
      return onWall(g) && spansBox(g) && g.parts_end - g.parts_begin >= 2;
    })) << "seed " << seed;
  }
}

// --- Invariants on random cluttered rooms ------------------------------------------------
TEST(ScanSegmenter, InvariantsHoldOnRandomClutteredRooms) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const ScanSegmenter segmenter;
  for (int trial = 0; trial < 60; ++trial) {
    const double w = 3 + 8 * u(rng), h = 2 + 6 * u(rng);
    sim::World world = rectangleRoom(w, h);
    const Pose2D pose{0.2 * w + 0.6 * w * u(rng), 0.2 * h + 0.6 * h * u(rng), 6.28 * u(rng)};
    for (int b = 0; b < 6; ++b) {
      const double x = w * u(rng), y = h * u(rng), s = 0.05 + 0.6 * u(rng);
      // Boxes stand clear of the sensor (0.3 m at least).
      if (pose.x > x - 0.3 && pose.x < x + s + 0.3 && pose.y > y - 0.3 && pose.y < y + s + 0.3) {
        continue;
      }
      world.addPolygon({{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}});
    }
    const auto sensor = trial % 2 ? makeSensor(541, 270, 0.012) : makeFullTurnSensor(360, 0.02);
    const Segmentation s = segmenter.process(simulate(world, sensor, pose, trial));
    expectInvariants(s);
    EXPECT_FALSE(segmentsAt(s, CascadeLevel::kFusedAgain).empty());
  }
}

// --- Bad input ----------------------------------------------------------------------------
Scan blankScan(std::size_t n) {
  Scan scan;
  scan.layout = std::make_shared<BeamLayout>(BeamLayout::centred(n, 3.0));
  scan.ranges_m.assign(n, 2.0);
  scan.max_range_m = 30.0;
  return scan;
}

TEST(ScanSegmenterBadInput, EmptyAllInvalidAndSingleBeamGiveNoSegment) {
  const ScanSegmenter segmenter;
  for (std::size_t n : {0u, 1u}) {
    const Segmentation s = segmenter.process(blankScan(n));
    for (const auto& level : s.levels) EXPECT_TRUE(level.segments.empty());
  }
  Scan invalid = blankScan(100);
  invalid.ranges_m.assign(100, std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(segmenter.process(invalid).levels[0].segments.empty());
  invalid.ranges_m.assign(100, 30.0);  // all at max range: no return
  EXPECT_EQ(segmenter.process(invalid).num_valid_beams, 0u);
  Scan single = blankScan(100);
  for (std::size_t i = 0; i < 100; ++i) single.ranges_m[i] = i == 50 ? 2.0 : -1.0;
  const Segmentation s = segmenter.process(single);
  EXPECT_EQ(s.num_valid_beams, 1u);
  EXPECT_TRUE(s.levels[0].segments.empty());
}

TEST(ScanSegmenterBadInput, NonFiniteAndNegativeRangesAreInvalidBeams) {
  const ScanSegmenter segmenter;
  Scan scan = blankScan(200);
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(), INFINITY, -INFINITY, -2.0, 0.0,
                        1e300};
  for (std::size_t i = 0; i < 6; ++i) scan.ranges_m[30 * i + 10] = bad[i];
  const Segmentation s = segmenter.process(scan);
  EXPECT_EQ(s.num_valid_beams, 194u);
  for (const auto& level : s.levels) {
    for (const Segment& g : level.segments) {
      EXPECT_TRUE(std::isfinite(g.rho_m));
      EXPECT_TRUE(std::isfinite(g.length_m));
    }
  }
  EXPECT_FALSE(s.levels[3].segments.empty());
}

TEST(ScanSegmenterBadInput, InconsistentScansThrowNamingTheField) {
  const ScanSegmenter segmenter;
  const auto expectMessage = [&](const Scan& scan, const char* field) {
    try {
      segmenter.process(scan);
      ADD_FAILURE() << "no exception for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  Scan s = blankScan(10);
  s.ranges_m.resize(9);
  expectMessage(s, "ranges_m");
  s = blankScan(10);
  s.valid.assign(11, 1);
  expectMessage(s, "valid");
  s = blankScan(10);
  s.time_offsets_s.assign(3, 0.0);
  expectMessage(s, "time_offsets_s");
  s = blankScan(10);
  s.layout.reset();
  expectMessage(s, "layout");
  s = blankScan(10);
  s.max_range_m = -1;
  expectMessage(s, "max_range_m");
}

TEST(ScanSegmenterBadInput, InvalidParametersAreRejectedWithTheirKey) {
  SegmentationParams p;
  p.noise.range_sigma_m = -0.01;
  try {
    ScanSegmenter{p};
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("range_sigma_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace lidarseg
