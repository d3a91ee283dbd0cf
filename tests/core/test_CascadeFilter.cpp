#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/CascadeFilter.h"

namespace lidarseg {
namespace {
using namespace lidarseg::testing;

// A noiseless segment from a to b sampled every 2 cm (sensor at the origin).
Segment makeSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::uint32_t index = 0) {
  Segment s;
  const int n = std::max(2, static_cast<int>((b - a).norm() / 0.02) + 1);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / (n - 1));
    s.moments.addPoint(p.x(), p.y());
  }
  s.num_points = static_cast<std::uint32_t>(n);
  s.first_point = a;
  s.last_point = b;
  s.parts_begin = index;
  s.parts_end = index + 1;
  fitSegment(s, SensorNoise{});
  return s;
}

SegmentLevel levelOf(std::vector<Segment> segments) {
  SegmentLevel l;
  for (std::uint32_t i = 0; i < segments.size(); ++i) {
    segments[i].parts_begin = i;
    segments[i].parts_end = i + 1;
    l.parts.push_back(i);
  }
  l.segments = std::move(segments);
  return l;
}

TEST(CascadeFilter, FusionCriteriaOfFigure1) {
  const FusionParams p;  // 5 deg, d = 0.04 m, D = 0.5 m
  const SensorNoise noise;  // 0.012 m
  const Segment a = makeSegment({1, 2}, {0, 2});
  EXPECT_TRUE(CascadeFilter::canFuse(a, makeSegment({-0.2, 2}, {-1.2, 2}), p, noise));
  // Not aligned: parallel but 10 cm behind (a recessed door).
  EXPECT_FALSE(CascadeFilter::canFuse(a, makeSegment({-0.2, 2.1}, {-1.2, 2.1}), p, noise));
  // Not close: a 1 m gap (a door opening).
  EXPECT_FALSE(CascadeFilter::canFuse(a, makeSegment({-1.0, 2}, {-2.0, 2}), p, noise));
  // Not parallel: 10 degrees apart.
  const double t = 10.0 * kDeg;
  EXPECT_FALSE(CascadeFilter::canFuse(
      a, makeSegment({-0.1, 2}, {-0.1 - std::cos(t), 2 + std::sin(t)}), p, noise));
}

// The noise gate fuses noisy pieces of one wall whose fitted lines disagree more than the
// angle and d tolerances allow, and still keeps a recessed door apart.
TEST(CascadeFilter, NoiseGateFusesNoisyPiecesOfOneWall) {
  FusionParams p;
  const SensorNoise noise{0.03, 0.0};
  // Two short pieces of the wall y = 2 whose noise tilted them 11 degrees apart.
  Segment a = makeSegment({1.0, 2.0}, {0.6, 2.0});
  Segment b = makeSegment({0.55, 2.0}, {0.25, 2.0});
  const auto tilt = [](Segment s, double dy) {
    s.moments = LineMoments{};
    const int n = 12;
    for (int i = 0; i < n; ++i) {
      const double f = static_cast<double>(i) / (n - 1);
      const Eigen::Vector2d q = s.first_point + f * (s.last_point - s.first_point);
      s.moments.addPoint(q.x(), q.y() + (f - 0.5) * dy);
    }
    fitSegment(s, SensorNoise{0.03, 0.0});
    return s;
  };
  a = tilt(a, 0.04);  // about +6 degrees
  b = tilt(b, -0.03);  // about -6 degrees
  EXPECT_FALSE(CascadeFilter::canFuse(a, b, {p.max_angle_rad, p.max_line_distance_m, p.max_gap_m, 0.0}, noise));
  EXPECT_TRUE(CascadeFilter::canFuse(a, b, p, noise));
  // A door recessed 5 cm is not noise at sigma = 1.2 cm.
  const Segment wall = makeSegment({3, 2}, {1, 2});
  const Segment door = makeSegment({0.95, 2.05}, {0.05, 2.05});
  EXPECT_FALSE(CascadeFilter::canFuse(wall, door, p, SensorNoise{}));
}

TEST(CascadeFilter, NanSegmentsNeverFuse) {
  const Segment a = makeSegment({1, 2}, {0, 2});
  Segment b = makeSegment({-0.2, 2}, {-1.2, 2});
  b.start = Eigen::Vector2d::Constant(std::nan(""));
  EXPECT_FALSE(CascadeFilter::canFuse(a, b, FusionParams{}, SensorNoise{}));
  // Not aligned, so only the noise gate could fuse it; NaN moments must not pass it.
  Segment c = makeSegment({-0.2, 2.3}, {-1.2, 2.3});
  c.moments.sum_xx = std::nan("");
  c.residual_ss_m2 = std::nan("");
  EXPECT_FALSE(CascadeFilter::canFuse(a, c, FusionParams{}, SensorNoise{0.5, 0.0}));
}

TEST(CascadeFilter, FusionRefitsFromTheUnionOfThePoints) {
  const CascadeFilter filter;
  const SegmentLevel in = levelOf({makeSegment({3, 2.0}, {1, 2.0}), makeSegment({0.9, 2.01}, {-1, 2.01}),
                                   makeSegment({-1.1, 2.0}, {-3, 2.0})});
  SegmentLevel out;
  filter.fuse(in, out, filter.params().first_fusion, false);
  ASSERT_EQ(out.segments.size(), 1u);
  const Segment& f = out.segments[0];
  Segment expected;
  expected.moments = in.segments[0].moments;
  expected.moments += in.segments[1].moments;
  expected.moments += in.segments[2].moments;
  expected.first_point = in.segments[0].first_point;
  expected.last_point = in.segments[2].last_point;
  fitSegment(expected, SensorNoise{});
  EXPECT_DOUBLE_EQ(f.rho_m, expected.rho_m);
  EXPECT_DOUBLE_EQ(f.theta_rad, expected.theta_rad);
  EXPECT_NEAR(f.length_m, 6.0, 1e-3);
  EXPECT_EQ(f.num_points, in.segments[0].num_points + in.segments[1].num_points +
                              in.segments[2].num_points);
  EXPECT_EQ(f.parts_begin, 0u);
  EXPECT_EQ(f.parts_end, 3u);
}

TEST(CascadeFilter, OnlyConsecutiveSegmentsFuse) {
  const CascadeFilter filter;
  // The middle segment is a box face in front of the wall: the wall's two sides stay apart.
  const SegmentLevel in = levelOf({makeSegment({3, 2}, {0.3, 2}), makeSegment({0.2, 1.8}, {-0.2, 1.8}),
                                   makeSegment({-0.3, 2}, {-3, 2})});
  SegmentLevel out;
  filter.fuse(in, out, filter.params().first_fusion, false);
  EXPECT_EQ(out.segments.size(), 3u);
}

TEST(CascadeFilter, ErosionRemovesShortSegmentsAndCompactsParts) {
  const CascadeFilter filter;  // min length 0.3 m, min 5 points
  const SegmentLevel in = levelOf({makeSegment({3, 2}, {0.3, 2}), makeSegment({0.2, 1.8}, {-0.0, 1.8}),
                                   makeSegment({-0.3, 2}, {-3, 2})});
  SegmentLevel out;
  filter.erode(in, out);
  ASSERT_EQ(out.segments.size(), 2u);
  EXPECT_EQ(out.parts, (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(out.segments[1].parts_begin, 1u);
  EXPECT_EQ(out.segments[1].parts_end, 2u);
}

TEST(CascadeFilter, WrapAroundFusionKeepsPartsContiguous) {
  const CascadeFilter filter;
  // In a full-turn scan the last segment continues into the first one.
  const SegmentLevel in = levelOf({makeSegment({-2, -0.1}, {-2, -1.5}), makeSegment({-1.5, -2}, {2, -2}),
                                   makeSegment({2, 2}, {-1.5, 2}), makeSegment({-2, 1.5}, {-2, 0.0})});
  SegmentLevel out;
  filter.fuse(in, out, filter.params().first_fusion, true);
  ASSERT_EQ(out.segments.size(), 3u);
  const Segment& merged = out.segments.back();
  EXPECT_NEAR(merged.length_m, 3.0, 1e-3);
  EXPECT_EQ(merged.parts_end - merged.parts_begin, 2u);
  EXPECT_EQ(out.parts[merged.parts_begin], 3u);
  EXPECT_EQ(out.parts[merged.parts_begin + 1], 0u);
  EXPECT_EQ(out.segments[0].parts_begin, 0u);
  EXPECT_EQ(out.parts[out.segments[0].parts_begin], 1u);
  // Without the wrap-around the two halves stay apart.
  filter.fuse(in, out, filter.params().first_fusion, false);
  EXPECT_EQ(out.segments.size(), 4u);
}

TEST(CascadeParams, ValidateNamesTheKey) {
  CascadeParams p;
  p.second_fusion.max_gap_m = -1;
  try {
    p.validate();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fusion2_max_gap_m"), std::string::npos) << e.what();
  }
  p = {};
  p.first_fusion.max_angle_rad = 2.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = {};
  p.erosion.min_length_m = INFINITY;
  EXPECT_THROW(CascadeFilter{p}, std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
