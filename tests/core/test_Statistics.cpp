#include <limits>

#include <gtest/gtest.h>

#include "lidarseg/core/Statistics.h"

namespace lidarseg {
namespace {

TEST(Statistics, SummaryOfKnownSample) {
  const Summary s = summarize({5, 1, 4, 2, 3});
  EXPECT_EQ(s.count, 5u);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 5.0);
  EXPECT_NEAR(s.stddev, 1.5811388300841898, 1e-12);  // sqrt(10 / 4)
  EXPECT_NEAR(s.p99, 4.96, 1e-12);                     // 4 + 0.96 * (5 - 4)
}

TEST(Statistics, EvenCountMedianInterpolates) {
  EXPECT_DOUBLE_EQ(summarize({1, 2, 3, 10}).median, 2.5);
}

TEST(Statistics, EmptyAndSingleton) {
  EXPECT_EQ(summarize({}).count, 0u);
  const Summary one = summarize({7});
  EXPECT_DOUBLE_EQ(one.median, 7.0);
  EXPECT_DOUBLE_EQ(one.p99, 7.0);
  EXPECT_DOUBLE_EQ(one.stddev, 0.0);
}

// The median of infinite values (a degenerate segment's θ sigma) was NaN: inf + 0 * (inf -
// inf) (issue 16).
TEST(Statistics, QuantilesOfInfiniteValuesAreNotNaN) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(summarize({inf, inf, inf}).median, inf);
  EXPECT_EQ(summarize({1, inf, inf}).median, inf);
  EXPECT_EQ(summarize({1, 2, inf}).median, 2.0);
  // Between an infinite sample and another: the nearer one, never NaN (-inf + f * (x + inf)).
  EXPECT_EQ(summarize({-inf, 1}).median, 1.0);
  EXPECT_EQ(summarize({-inf, -inf, 1, 2}).median, 1.0);  // half-way: the upper one
  EXPECT_EQ(quantileSorted({-inf, inf}, 0.25), -inf);
  EXPECT_EQ(quantileSorted({-inf, inf}, 0.75), inf);
  EXPECT_EQ(quantileSorted({1, inf}, 0.99), inf);
  EXPECT_EQ(quantileSorted({-inf, 3}, 0.2), -inf);
  EXPECT_EQ(summarize({-inf, 0, inf}).p99, inf);
}

}  // namespace
}  // namespace lidarseg
