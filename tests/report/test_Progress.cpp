// The time left a progress line shows: from the items' rate when their total is known, else
// from the share of the input read.
#include <gtest/gtest.h>

#include "lidarseg/report/Progress.h"

namespace lidarseg::report {
namespace {

TEST(Progress, TimeLeftFromTheTotalWhenKnown) {
  EXPECT_DOUBLE_EQ(secondsLeft(10.0, 25, 100, -1.0), 30.0);  // 2.5 items a second, 75 to go
  EXPECT_DOUBLE_EQ(secondsLeft(10.0, 25, 100, 0.9), 30.0);   // the total wins over the share
  EXPECT_LT(secondsLeft(10.0, 0, 100, -1.0), 0.0);           // no rate yet
  EXPECT_LT(secondsLeft(10.0, 100, 100, -1.0), 0.0);         // done
  EXPECT_LT(secondsLeft(10.0, 120, 100, -1.0), 0.0);         // past a total that was a cap
}

TEST(Progress, TimeLeftFromTheShareReadWithoutATotal) {
  EXPECT_DOUBLE_EQ(secondsLeft(10.0, 7, 0, 0.25), 30.0);  // a quarter in 10 s: 30 s more
  EXPECT_DOUBLE_EQ(secondsLeft(30.0, 7, 0, 0.75), 10.0);
  EXPECT_LT(secondsLeft(10.0, 7, 0, -1.0), 0.0);  // no share: not known
  EXPECT_LT(secondsLeft(10.0, 7, 0, 0.0), 0.0);
  EXPECT_LT(secondsLeft(10.0, 7, 0, 1.0), 0.0);   // all read
  EXPECT_LT(secondsLeft(0.0, 7, 0, 0.5), 0.0);    // no time elapsed yet
}

}  // namespace
}  // namespace lidarseg::report
