// The segment matcher on synthetic scans with known motion.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/SegmentMatcher.h"

namespace lidarseg {
namespace {
using namespace lidarseg::testing;

struct Pair {
  Segmentation previous, current;
};

Pair scansOf(const sim::World& world, const Pose2D& T_world_prev, const Pose2D& T_prev_curr,
             double sigma) {
  const auto sensor = makeSensor(541, 270, sigma);
  SegmentationParams p;
  p.noise.range_sigma_m = std::max(sigma, 1e-3);
  const ScanSegmenter seg(p);
  return {seg.process(simulate(world, sensor, T_world_prev, 1)),
          seg.process(simulate(world, sensor, compose(T_world_prev, T_prev_curr), 2))};
}

class MatcherMotions : public ::testing::TestWithParam<Pose2D> {};

// Office scene: the matcher recovers the motion between two scans from a rough prior.
TEST_P(MatcherMotions, RecoversTheMotionInAnOffice) {
  const Pose2D truth = GetParam();
  const Pair s = scansOf(officeScene(), {-3.0, 1.0, 0.2}, truth, 0.012);
  const SegmentMatcher matcher;
  // The prior is off by 5 cm and 2 degrees, like a constant-velocity prediction.
  const Pose2D prior{truth.x + 0.05, truth.y - 0.03, truth.yaw + 2.0 * kDeg};
  const MatchResult r = matcher.match(s.previous.levels[3].segments, s.current.levels[3].segments, prior);
  ASSERT_NE(r.status, MatchStatus::kTooFewMatches);
  EXPECT_GE(r.matches.size(), 3u);
  EXPECT_NEAR(r.T_prev_curr.yaw, truth.yaw, 0.003);
  if (r.status == MatchStatus::kOk) {
    EXPECT_NEAR(r.T_prev_curr.x, truth.x, 0.02);
    EXPECT_NEAR(r.T_prev_curr.y, truth.y, 0.02);
  }
  EXPECT_GT(r.covariance(0, 0), 0.0);
  EXPECT_GT(r.covariance(2, 2), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Motions, MatcherMotions,
                         ::testing::Values(Pose2D{0.0, 0.0, 0.0}, Pose2D{0.2, 0.0, 0.0},
                                           Pose2D{0.3, 0.05, 0.05}, Pose2D{0.1, -0.05, -0.1},
                                           Pose2D{0.0, 0.0, 0.25}));

// A corridor of two parallel walls only: the translation along it is unconstrained; the
// matcher says so and keeps the prediction there.
TEST(SegmentMatcher, DegenerateCorridorKeepsThePredictionAlongIt) {
  sim::World corridor;
  corridor.addWall({-30, 0}, {30, 0});
  corridor.addWall({-30, 2}, {30, 2});
  const Pose2D truth{0.3, 0.02, 0.01};
  const Pair s = scansOf(corridor, {0, 1, 0}, truth, 0.01);
  const SegmentMatcher matcher;
  const Pose2D prior{0.25, 0.0, 0.0};
  const MatchResult r = matcher.match(s.previous.levels[3].segments, s.current.levels[3].segments, prior);
  ASSERT_EQ(r.status, MatchStatus::kDegenerate);
  EXPECT_NEAR(std::abs(r.degenerate_direction.x()), 1.0, 0.05);
  EXPECT_NEAR(r.T_prev_curr.y, truth.y, 0.01);
  EXPECT_NEAR(r.T_prev_curr.yaw, truth.yaw, 0.002);
  EXPECT_NEAR(r.T_prev_curr.x, prior.x, 0.02);  // along the corridor: the prediction
  EXPECT_GT(r.covariance(0, 0), 100 * r.covariance(1, 1));
}

TEST(SegmentMatcher, NothingToMatchReturnsThePrior) {
  const SegmentMatcher matcher;
  const Pose2D prior{0.1, 0.2, 0.3};
  const MatchResult r = matcher.match({}, {}, prior);
  EXPECT_EQ(r.status, MatchStatus::kTooFewMatches);
  EXPECT_EQ(r.T_prev_curr.x, prior.x);
  EXPECT_EQ(r.T_prev_curr.yaw, prior.yaw);
}

// A non-finite prior predicts nothing: no match, no weight computed from it.
TEST(SegmentMatcher, ANonFinitePriorMatchesNothing) {
  const Pair s = scansOf(officeScene(), {-3.0, 1.0, 0.2}, {0.1, 0.0, 0.02}, 0.012);
  const MatchResult r = SegmentMatcher().match(s.previous.levels[3].segments, s.current.levels[3].segments,
                                               Pose2D{std::nan(""), 0.0, 0.0});
  EXPECT_EQ(r.status, MatchStatus::kTooFewMatches);
  EXPECT_TRUE(r.matches.empty());
  EXPECT_TRUE(r.covariance.allFinite());
}

TEST(SegmentMatcher, FocusedBandComputesFewerWeightsThanTheFullMatrix) {
  const Pair s = scansOf(officeScene(), {-3.0, 1.0, 0.2}, {0.1, 0.0, 0.02}, 0.012);
  MatcherParams banded, full;
  full.band_half_width = 0;
  const auto& a = s.previous.levels[0].segments;  // many segments: the band matters
  const auto& b = s.current.levels[0].segments;
  const MatchResult rb = SegmentMatcher(banded).match(a, b, {0.1, 0.0, 0.02});
  const MatchResult rf = SegmentMatcher(full).match(a, b, {0.1, 0.0, 0.02});
  EXPECT_LT(rb.weights_computed, rf.weights_computed);
  EXPECT_GT(rf.weights_gated, 0u);
  EXPECT_NEAR(rb.T_prev_curr.x, rf.T_prev_curr.x, 0.02);
}

TEST(MatcherParams, ValidateNamesTheKey) {
  MatcherParams p;
  p.max_weight = -1;
  try {
    p.validate();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_weight"), std::string::npos);
  }
}

// One matcher shared by threads (its scratch memory is per thread): the same results as
// one thread. The ThreadSanitizer build (./run.sh tsan) runs this test.
TEST(SegmentMatcher, OneMatcherSharedByThreadsGivesTheSerialResults) {
  const Pair s = scansOf(officeScene(), {-3.0, 1.0, 0.2}, {0.2, 0.03, 0.05}, 0.012);
  const SegmentMatcher matcher;
  const auto& a = s.previous.levels[3].segments;
  const auto& b = s.current.levels[3].segments;
  std::vector<Pose2D> priors;
  for (int k = 0; k < 8; ++k) priors.push_back({0.2 + 0.01 * k, 0.03, 0.05 - 0.005 * k});
  std::vector<MatchResult> serial;
  for (const Pose2D& p : priors) serial.push_back(matcher.match(a, b, p));
  std::vector<MatchResult> parallel(priors.size());
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int repeat = 0; repeat < 20; ++repeat) {
        for (std::size_t k = t; k < priors.size(); k += 4) parallel[k] = matcher.match(a, b, priors[k]);
      }
    });
  }
  for (auto& th : threads) th.join();
  for (std::size_t k = 0; k < priors.size(); ++k) {
    EXPECT_EQ(parallel[k].status, serial[k].status);
    EXPECT_EQ(parallel[k].matches, serial[k].matches);
    EXPECT_EQ(parallel[k].T_prev_curr.x, serial[k].T_prev_curr.x);
    EXPECT_EQ(parallel[k].T_prev_curr.yaw, serial[k].T_prev_curr.yaw);
  }
}

// max_segments bounds the work whatever the scan holds: the longest segments are kept and
// the matches refer to the caller's indices.
TEST(SegmentMatcher, MaxSegmentsBoundsTheWorkAndKeepsTheCallersIndices) {
  const Pair s = scansOf(officeScene(), {-3.0, 1.0, 0.2}, {0.2, 0.03, 0.05}, 0.012);
  const auto& a = s.previous.levels[0].segments;
  const auto& b = s.current.levels[0].segments;
  ASSERT_GT(a.size(), 8u);
  MatcherParams p;
  p.max_segments = 8;
  p.band_half_width = 0;  // the full matrix: the worst case
  const MatchResult r = SegmentMatcher(p).match(a, b, {0.2, 0.03, 0.05});
  EXPECT_EQ(r.segments_ignored, a.size() - 8 + b.size() - std::min<std::size_t>(8, b.size()));
  EXPECT_LE(r.weights_computed, 2 * (p.iterations + 1) * 8 * 8);
  std::vector<double> lengths;
  for (const auto& seg : a) lengths.push_back(seg.length_m);
  std::sort(lengths.begin(), lengths.end(), std::greater<>());
  for (const auto& [i, j] : r.matches) {
    ASSERT_LT(static_cast<std::size_t>(i), a.size());
    ASSERT_LT(static_cast<std::size_t>(j), b.size());
    EXPECT_GE(a[static_cast<std::size_t>(i)].length_m, lengths[7]);  // one of the 8 longest
  }
  p.max_segments = 1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

// A 1 m segment of the line through `middle` with normal angle theta (rad), noiseless: the
// matcher's floors min_rho_sigma_m and min_theta_sigma_rad stand for its covariance.
Segment lineSegment(const Eigen::Vector2d& middle, double theta) {
  Segment s;
  s.theta_rad = theta;
  s.normal = {std::cos(theta), std::sin(theta)};
  s.rho_m = s.normal.dot(middle);
  const Eigen::Vector2d along(-s.normal.y(), s.normal.x());
  s.start = s.first_point = middle - 0.5 * along;
  s.end = s.last_point = middle + 0.5 * along;
  s.cog = s.centroid = middle;
  s.length_m = 1.0;
  return s;
}

// The second iteration re-associates, gains a couple whose lines disagree by 0.12 rad, and its
// outlier test then drops every couple: that iteration is discarded whole. The result is the
// first iteration's estimate, with the covariance and the couples of that same estimate (the
// matcher used to return the discarded iteration's pose and covariance with the first one's
// couples).
TEST(SegmentMatcher, AnIterationLeftWithoutCouplesGivesBackThePreviousEstimateWhole) {
  const Pose2D truth{0.3, 0.0, 0.0};  // T_prev_curr: the current sensor is 0.3 m further along x
  const Pose2D T_curr_prev = inverse(truth);
  const std::vector<Segment> previous = {lineSegment({5, 0}, 0.0), lineSegment({0, 5}, 0.5 * kPi),
                                         lineSegment({-5, 0}, kPi)};
  // The first two walls seen again; the third is another wall, turned by 0.12 rad. From the
  // prior (identity) its weight is above max_weight; from the first estimate it is not.
  const std::vector<Segment> current = {
      lineSegment(T_curr_prev * Eigen::Vector2d(5, 0), 0.0),
      lineSegment(T_curr_prev * Eigen::Vector2d(0, 5), 0.5 * kPi),
      lineSegment(T_curr_prev * Eigen::Vector2d(-5, 0), kPi + 0.12)};
  const MatcherParams params;  // 2 re-association iterations
  const MatchResult r = SegmentMatcher(params).match(previous, current, Pose2D{});
  // The case is the one described: the second iteration reached the solve, and its outlier
  // test dropped its three couples.
  ASSERT_EQ(r.iterations, 2u);
  ASSERT_EQ(r.rejections.outliers, 3u);

  const std::vector<std::pair<int, int>> first_couples = {{0, 0}, {1, 1}};
  EXPECT_EQ(r.status, MatchStatus::kOk);
  EXPECT_EQ(r.matches, first_couples);
  // The pose those two couples give: exact, the lines are noiseless.
  EXPECT_NEAR(r.T_prev_curr.x, truth.x, 1e-9);
  EXPECT_NEAR(r.T_prev_curr.y, truth.y, 1e-9);
  EXPECT_NEAR(r.T_prev_curr.yaw, truth.yaw, 1e-9);
  // Their covariance: the two lines are orthogonal, each fixes one axis alone with its
  // couple's rho variance 2 min_rho_sigma_m^2; the yaw is the mean of two angle differences
  // of variance 2 min_theta_sigma_rad^2 each.
  const double var_rho = 2.0 * params.min_rho_sigma_m * params.min_rho_sigma_m;
  const double var_theta = 2.0 * params.min_theta_sigma_rad * params.min_theta_sigma_rad;
  EXPECT_NEAR(r.covariance(0, 0), var_rho, 1e-3 * var_rho);
  EXPECT_NEAR(r.covariance(1, 1), var_rho, 1e-3 * var_rho);
  EXPECT_NEAR(r.covariance(2, 2), 0.5 * var_theta, 1e-3 * var_theta);
  EXPECT_NEAR(r.covariance(0, 1), 0.0, 1e-6 * var_rho);

  // The same as a matcher that stops after the first iteration, field by field.
  MatcherParams once = params;
  once.iterations = 0;
  const MatchResult r1 = SegmentMatcher(once).match(previous, current, Pose2D{});
  ASSERT_EQ(r1.iterations, 1u);
  EXPECT_EQ(r.status, r1.status);
  EXPECT_EQ(r.matches, r1.matches);
  EXPECT_EQ(r.T_prev_curr.x, r1.T_prev_curr.x);
  EXPECT_EQ(r.T_prev_curr.y, r1.T_prev_curr.y);
  EXPECT_EQ(r.T_prev_curr.yaw, r1.T_prev_curr.yaw);
  EXPECT_EQ(r.covariance, r1.covariance);
  EXPECT_EQ(r.degenerate_direction, r1.degenerate_direction);
}

// Couples of lines without a usable covariance (infinite: fitSegment's value for fewer than 2
// points) give no pose; the result is the prior, and no couples are reported with it.
TEST(SegmentMatcher, CouplesWithoutAPoseAreNotReported) {
  std::vector<Segment> lines = {lineSegment({5, 0}, 0.0), lineSegment({0, 5}, 0.5 * kPi)};
  for (Segment& s : lines) s.covariance.setConstant(std::numeric_limits<double>::infinity());
  const Pose2D prior{0.01, 0.02, 0.03};
  const MatchResult r = SegmentMatcher().match(lines, lines, prior);
  ASSERT_GE(r.iterations, 1u);  // the two couples were found and reached the solve
  EXPECT_EQ(r.status, MatchStatus::kTooFewMatches);
  EXPECT_TRUE(r.matches.empty());
  EXPECT_EQ(r.T_prev_curr.x, prior.x);
  EXPECT_EQ(r.T_prev_curr.y, prior.y);
  EXPECT_EQ(r.T_prev_curr.yaw, prior.yaw);
}

// Issue 16: `iterations = 1000000000` was accepted and a match hung; the counts that drive
// a match's work are capped.
TEST(MatcherParams, IterationsAndMaxSegmentsAreBounded) {
  MatcherParams p;
  p.iterations = 1000000000;
  try {
    p.validate();
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("iterations must be <= 1000", 0), 0u) << e.what();
  }
  p.iterations = MatcherParams::kMaxIterations;
  EXPECT_NO_THROW(p.validate());
  p = {};
  p.max_segments = MatcherParams::kMaxSegments + 1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p.max_segments = MatcherParams::kMaxSegments;
  EXPECT_NO_THROW(p.validate());
}

}  // namespace
}  // namespace lidarseg
