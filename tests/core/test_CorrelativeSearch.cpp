// Correlative search: finds a pose far from a wrong prior; its result equals the brute force.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "SyntheticScenes.h"

namespace lidarseg {
namespace {

std::vector<Eigen::Vector2d> pointsAt(const sim::World& world, const Pose2D& pose, std::uint64_t seed) {
  const auto sensor = testing::makeSensor(541, 270.0, 0.01, 30.0);
  Segmentation seg;
  ScanSegmenter().process(testing::simulate(world, sensor, pose, seed), seg);
  return seg.points;
}

TEST(CorrelativeSearch, FindsAOneMetreThirtyDegreeJumpFromAZeroPrior) {
  const sim::World world = testing::officeScene();
  const Pose2D a{0.0, 1.0, 0.0};
  const Pose2D b{0.9, 1.4, 0.5};  // 1 m and 29 degrees from a
  const auto key = pointsAt(world, a, 1);
  const auto cur = pointsAt(world, b, 2);
  const SearchResult r = CorrelativeSearch().search(key, cur, Pose2D{});
  ASSERT_TRUE(r.found);
  const Pose2D truth = relative(b, a);
  EXPECT_NEAR(r.T_key_curr.x, truth.x, 0.06);
  EXPECT_NEAR(r.T_key_curr.y, truth.y, 0.06);
  EXPECT_NEAR(r.T_key_curr.yaw, truth.yaw, 0.02);
  EXPECT_GT(r.score, r.prior_score + 0.2);
}

// A non-finite prior has no window: nothing found, no undefined grid index (a NaN prior
// from SegmentAlignment's initial estimate crashed here).
TEST(CorrelativeSearch, ANonFinitePriorFindsNothing) {
  const sim::World world = testing::officeScene();
  const auto key = pointsAt(world, {0.0, 1.0, 0.0}, 1);
  const auto cur = pointsAt(world, {0.1, 1.0, 0.0}, 2);
  const double nan = std::nan(""), inf = HUGE_VAL;
  for (const Pose2D prior : {Pose2D{nan, 0.0, 0.0}, Pose2D{0.0, -inf, 0.0}, Pose2D{0.0, 0.0, nan}}) {
    const SearchResult r = CorrelativeSearch().search(key, cur, prior);
    EXPECT_FALSE(r.found);
  }
  EXPECT_TRUE(CorrelativeSearch().search(key, cur, Pose2D{}).found);
}

// The branch and bound returns the best pose of the full grid: check it against scoring
// every pose of a small window by brute force.
TEST(CorrelativeSearch, BranchAndBoundEqualsTheFullGridSearch) {
  const sim::World world = testing::officeScene();
  const auto key = pointsAt(world, {0.0, 1.0, 0.0}, 3);
  const auto cur = pointsAt(world, {0.2, 1.1, 0.05}, 4);
  SearchParams fast;
  fast.linear_window_m = 0.3;
  fast.angular_window_rad = 0.1;
  fast.angular_step_rad = 0.02;
  SearchParams brute = fast;
  brute.coarse_cells = 1;  // every pose is a candidate, sorted by its exact score
  const SearchResult f = CorrelativeSearch(fast).search(key, cur, Pose2D{});
  const SearchResult b = CorrelativeSearch(brute).search(key, cur, Pose2D{});
  EXPECT_FLOAT_EQ(static_cast<float>(f.score), static_cast<float>(b.score));
  EXPECT_LT(f.bounds, b.bounds);  // the coarse level prunes: far fewer poses scored
}

// Every top-level block side, power of two or not, gives the full search's pose (the levels
// below halve it, rounded up), with less than half the scoring passes of the full search.
TEST(CorrelativeSearch, EveryBlockSideGivesTheFullSearchPose) {
  const sim::World world = testing::officeScene();
  const auto key = pointsAt(world, {0.0, 1.0, 0.0}, 5);
  const auto cur = pointsAt(world, {0.35, 1.2, -0.08}, 6);
  SearchParams brute;
  brute.linear_window_m = 0.5;
  brute.angular_window_rad = 0.15;
  brute.angular_step_rad = 0.01;
  brute.coarse_cells = 1;
  const SearchResult b = CorrelativeSearch(brute).search(key, cur, Pose2D{});
  ASSERT_TRUE(b.found);
  const std::size_t poses = b.bounds;  // with blocks of one cell, every pose is scored once
  for (std::size_t side : {2u, 3u, 5u, 6u, 8u, 13u, 16u, 32u}) {
    SCOPED_TRACE("coarse_cells " + std::to_string(side));
    SearchParams p = brute;
    p.coarse_cells = side;
    const SearchResult r = CorrelativeSearch(p).search(key, cur, Pose2D{});
    EXPECT_FLOAT_EQ(static_cast<float>(r.score), static_cast<float>(b.score));
    EXPECT_DOUBLE_EQ(r.T_key_curr.x, b.T_key_curr.x);
    EXPECT_DOUBLE_EQ(r.T_key_curr.y, b.T_key_curr.y);
    EXPECT_DOUBLE_EQ(r.T_key_curr.yaw, b.T_key_curr.yaw);
    EXPECT_LT(r.bounds + r.evaluated, poses / 2);
  }
}

// A keyframe prepared once serves several scans with the results of preparing it each time;
// a grid never prepared finds nothing.
TEST(CorrelativeSearch, APreparedKeyframeGivesTheSameResults) {
  const sim::World world = testing::officeScene();
  const auto key = pointsAt(world, {0.0, 1.0, 0.0}, 7);
  const CorrelativeSearch search;
  SearchGrid grid;
  EXPECT_FALSE(search.search(grid, key, Pose2D{}).found);
  search.prepare(key, grid);
  ASSERT_TRUE(grid.ready);
  for (const Pose2D& pose : {Pose2D{0.5, 1.3, 0.2}, Pose2D{-0.4, 0.8, -0.3}}) {
    const auto cur = pointsAt(world, pose, 8);
    const SearchResult once = search.search(key, cur, Pose2D{});
    const SearchResult prepared = search.search(grid, cur, Pose2D{});
    EXPECT_EQ(once.found, prepared.found);
    EXPECT_DOUBLE_EQ(once.score, prepared.score);
    EXPECT_DOUBLE_EQ(once.T_key_curr.x, prepared.T_key_curr.x);
    EXPECT_DOUBLE_EQ(once.T_key_curr.y, prepared.T_key_curr.y);
    EXPECT_DOUBLE_EQ(once.T_key_curr.yaw, prepared.T_key_curr.yaw);
    const Pose2D truth = relative(pose, {0.0, 1.0, 0.0});
    EXPECT_NEAR(prepared.T_key_curr.x, truth.x, 0.06);
    EXPECT_NEAR(prepared.T_key_curr.y, truth.y, 0.06);
  }
}

// A wider search given the narrower one's best score as its floor (decision 83): a pose the
// narrow window holds cannot come back; one outside it that scores higher is found, as by the
// wide search without a floor, with fewer poses scored.
TEST(CorrelativeSearch, AScoreFloorReturnsOnlyPosesThatBeatIt) {
  const sim::World world = testing::officeScene();
  const Pose2D a{0.0, 1.0, 0.0};
  const Pose2D b{1.9, 1.2, 0.1};  // 1.9 m from a: outside the narrow window, inside the wide one
  const auto key = pointsAt(world, a, 7);
  const auto cur = pointsAt(world, b, 8);
  SearchParams narrow;
  narrow.linear_window_m = 1.0;
  SearchParams wide = narrow;
  wide.linear_window_m = 2.4;
  CorrelativeSearch wide_search(wide);
  SearchGrid grid;
  wide_search.prepare(key, grid);
  const SearchResult n = CorrelativeSearch(narrow).search(grid, cur, Pose2D{});
  const SearchResult w = wide_search.search(grid, cur, Pose2D{});
  const SearchResult floored = wide_search.search(grid, cur, Pose2D{}, n.score);
  ASSERT_TRUE(n.found);
  ASSERT_TRUE(w.found);
  const Pose2D truth = relative(b, a);
  EXPECT_GT(std::hypot(n.T_key_curr.x - truth.x, n.T_key_curr.y - truth.y), 0.5);  // the narrow one cannot reach it
  EXPECT_NEAR(w.T_key_curr.x, truth.x, 0.06);
  EXPECT_NEAR(w.T_key_curr.y, truth.y, 0.06);
  ASSERT_TRUE(floored.found);
  EXPECT_EQ(floored.T_key_curr.x, w.T_key_curr.x);
  EXPECT_EQ(floored.T_key_curr.y, w.T_key_curr.y);
  EXPECT_EQ(floored.T_key_curr.yaw, w.T_key_curr.yaw);
  EXPECT_DOUBLE_EQ(floored.score, w.score);
  EXPECT_LT(floored.evaluated + floored.bounds, w.evaluated + w.bounds);
  // Nothing beats the wide search's own best: with it as the floor, nothing is found.
  const SearchResult none = wide_search.search(grid, cur, Pose2D{}, w.score);
  EXPECT_FALSE(none.found);
  EXPECT_EQ(none.score, 0.0);
}

// The score the search maximises, recomputed here from the likelihood grid with every
// lookup tested: the search's best equals the maximum over every pose of the window, also
// with a keyframe grid clipped around the sensor (max_grid_cells), where many of the current
// scan's points fall near its edge or beyond it and the search reads them its other ways.
TEST(CorrelativeSearch, TheBestIsTheMaximumOfTheScoreRecomputedCellByCell) {
  const sim::World world = testing::officeScene();
  const auto key = pointsAt(world, {0.0, 1.0, 0.0}, 9);
  const auto cur = pointsAt(world, {0.25, 1.1, 0.05}, 10);
  for (const std::size_t grid_cells : {std::size_t{1200}, std::size_t{60}, std::size_t{40}}) {
    SCOPED_TRACE("max_grid_cells " + std::to_string(grid_cells));
    SearchParams p;
    p.linear_window_m = 0.4;       // W = 8 cells
    p.angular_window_rad = 0.1;    // A = 10 steps
    p.angular_step_rad = 0.01;
    p.max_points = 5000;           // every valid point is used
    p.coarse_cells = 4;
    p.max_grid_cells = grid_cells;
    const CorrelativeSearch search(p);
    SearchGrid g;
    search.prepare(key, g);
    const SearchResult r = search.search(g, cur, Pose2D{});
    ASSERT_TRUE(r.found);

    const int pad = g.pad, pw = g.w + 2 * pad, ph = g.h + 2 * pad;
    const std::vector<SearchGrid::Cell>& likelihood = g.levels.back();
    std::size_t n = 0, outside = 0;
    for (const auto& q : cur) n += std::isfinite(q.x()) && std::isfinite(q.y());
    const auto sumAt = [&](int a, int ix, int iy) {
      const double yaw = (a - 10) * 0.01, c = std::cos(yaw), s = std::sin(yaw);
      long sum = 0;
      for (const auto& q : cur) {
        if (!(std::isfinite(q.x()) && std::isfinite(q.y()))) continue;
        const double x = c * q.x() - s * q.y(), y = s * q.x() + c * q.y();
        const int i = static_cast<int>(std::floor((x - g.x0) / g.res)) + ix + pad;
        const int j = static_cast<int>(std::floor((y - g.y0) / g.res)) + iy + pad;
        if (i < 0 || j < 0 || i >= pw || j >= ph) {
          ++outside;
          continue;
        }
        sum += likelihood[static_cast<std::size_t>(j) * static_cast<std::size_t>(pw) + static_cast<std::size_t>(i)];
      }
      return sum;
    };
    long best = -1;
    for (int a = 0; a <= 20; ++a) {
      for (int iy = -8; iy <= 8; ++iy) {
        for (int ix = -8; ix <= 8; ++ix) best = std::max(best, sumAt(a, ix, iy));
      }
    }
    const double scale = SearchGrid::kCellMax * static_cast<double>(n);
    EXPECT_DOUBLE_EQ(r.score, static_cast<double>(best) / scale);
    const int a = static_cast<int>(std::lround(r.T_key_curr.yaw / 0.01)) + 10;
    const int ix = static_cast<int>(std::lround(r.T_key_curr.x / g.res));
    const int iy = static_cast<int>(std::lround(r.T_key_curr.y / g.res));
    EXPECT_EQ(sumAt(a, ix, iy), best);
    EXPECT_DOUBLE_EQ(r.prior_score, static_cast<double>(sumAt(10, 0, 0)) / scale);
    if (grid_cells < 100) {
      EXPECT_GT(outside, 0u);  // the clipped grids do leave points outside
    }
  }
}

TEST(CorrelativeSearch, EmptyInputsAndBadParameters) {
  const std::vector<Eigen::Vector2d> none;
  const std::vector<Eigen::Vector2d> nan(10, Eigen::Vector2d(std::nan(""), 1.0));
  EXPECT_FALSE(CorrelativeSearch().search(none, none, Pose2D{}).found);
  EXPECT_FALSE(CorrelativeSearch().search(nan, nan, Pose2D{}).found);
  SearchParams p;
  p.resolution_m = 0.0;
  EXPECT_THROW(CorrelativeSearch{p}, std::invalid_argument);
  p = {};
  p.coarse_cells = 0;
  EXPECT_THROW(CorrelativeSearch{p}, std::invalid_argument);
}

// Issue 16: a rotation step of 1e-12 rad passed validation and the search tried 10^12
// rotations (SIGSEGV, bad_alloc or a hang). 0 (automatic) or >= 0.0005 rad now.
TEST(CorrelativeSearch, TheRotationStepIsAutomaticOrAtLeastHalfAMilliradian) {
  for (const double bad : {1e-12, 1e-9, 1e-6, 4.9e-4, -0.01, 0.51, std::nan("")}) {
    SearchParams p;
    p.angular_step_rad = bad;
    try {
      p.validate();
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("angular_step_rad must be 0 (automatic) or in [0.0005, 0.5]", 0), 0u)
          << e.what();
    }
  }
  for (const double good : {0.0, SearchParams::kMinAngularStepRad, 0.01, 0.5}) {
    SearchParams p;
    p.angular_step_rad = good;
    EXPECT_NO_THROW(p.validate()) << good;
  }
  // The smallest step over the widest window is a bounded search that still finds the pose.
  SearchParams fine;
  fine.angular_step_rad = SearchParams::kMinAngularStepRad;
  fine.angular_window_rad = 0.05;
  fine.linear_window_m = 0.2;
  const sim::World world = testing::officeScene();
  const Pose2D a{0.0, 1.0, 0.0};
  const Pose2D b{0.05, 1.0, 0.02};
  const SearchResult r = CorrelativeSearch(fine).search(pointsAt(world, a, 1), pointsAt(world, b, 2), Pose2D{});
  ASSERT_TRUE(r.found);
  const Pose2D truth = relative(b, a);
  EXPECT_NEAR(r.T_key_curr.x, truth.x, 0.06);
  EXPECT_NEAR(r.T_key_curr.yaw, truth.yaw, 0.01);
}

}  // namespace
}  // namespace lidarseg
