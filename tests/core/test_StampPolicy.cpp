#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "lidarseg/core/StampPolicy.h"

namespace lidarseg {
namespace {

// Feeds the stamps through the policy, accepting each step.
std::vector<StampStep> run(StampPolicy& policy, const std::vector<double>& stamps) {
  std::vector<StampStep> out;
  for (double t : stamps) {
    out.push_back(policy.next(t));
    policy.accept(out.back());
  }
  return out;
}

TEST(StampPolicy, IncreasingStampsPassThrough) {
  StampPolicy p;
  const auto s = run(p, {10.0, 10.1, 10.2});
  EXPECT_TRUE(s[0].first);
  EXPECT_DOUBLE_EQ(s[0].dt_s, 0.0);
  EXPECT_NEAR(s[2].dt_s, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(s[2].model_stamp_s, 10.2);
  EXPECT_DOUBLE_EQ(s[2].output_stamp_s, 10.2);
  EXPECT_FALSE(s[2].gap || s[2].non_increasing);
}

TEST(StampPolicy, ARepeatedOrBackwardsStampUsesTheLastGoodStepAndStillIncreasesTheOutput) {
  StampPolicyParams params;
  params.output_nudge_s = 0.002;
  StampPolicy p(params);
  const auto s = run(p, {1.0, 1.05, 1.05, 0.9, 1.2});
  EXPECT_TRUE(s[2].non_increasing);
  EXPECT_NEAR(s[2].dt_s, 0.05, 1e-12);
  EXPECT_NEAR(s[2].model_stamp_s, 1.10, 1e-12);
  EXPECT_NEAR(s[2].output_stamp_s, 1.052, 1e-12);
  EXPECT_TRUE(s[3].non_increasing);
  EXPECT_NEAR(s[3].model_stamp_s, 1.15, 1e-12);
  EXPECT_NEAR(s[3].output_stamp_s, 1.054, 1e-12);
  // After a backwards stamp the log's own step counts again: 1.2 - 0.9.
  EXPECT_NEAR(s[4].dt_s, 0.3, 1e-12);
  for (std::size_t k = 1; k < s.size(); ++k) EXPECT_GT(s[k].output_stamp_s, s[k - 1].output_stamp_s);
}

// With epoch stamps a nudge can be below the stamps' resolution: the output still increases.
TEST(StampPolicy, RepeatedEpochStampsStillIncreaseTheOutput) {
  StampPolicyParams params;
  params.output_nudge_s = 1e-6;
  StampPolicy p(params);
  const double t0 = 4e9;  // year 2096: a double's step there is 4.8e-7 s
  const auto s = run(p, std::vector<double>(50, t0));
  for (std::size_t k = 1; k < s.size(); ++k) EXPECT_GT(s[k].output_stamp_s, s[k - 1].output_stamp_s) << k;
  params.output_nudge_s = 1e-12;
  EXPECT_THROW(StampPolicy{params}, std::invalid_argument);
}

TEST(StampPolicy, AGapIsFlaggedAndItsStepIsNotTheNextRepairStep) {
  StampPolicy p;
  const auto s = run(p, {0.0, 0.1, 5.0, 5.0});
  EXPECT_TRUE(s[2].gap);
  EXPECT_NEAR(s[2].dt_s, 4.9, 1e-12);
  EXPECT_TRUE(s[3].non_increasing);
  EXPECT_NEAR(s[3].dt_s, 0.1, 1e-12);  // the last good step, not the gap
}

TEST(StampPolicy, AClockJumpingBackADayIsAGapNotARepeatedStamp) {
  StampPolicy p;
  const auto s = run(p, {86400.0, 86400.1, 0.2, 0.3});
  EXPECT_TRUE(s[2].clock_jump);
  EXPECT_TRUE(s[2].gap);
  EXPECT_FALSE(s[2].non_increasing);
  EXPECT_NEAR(s[2].dt_s, 0.1, 1e-9);  // the model's clock goes on by the last good step
  EXPECT_FALSE(s[3].gap || s[3].non_increasing);
  EXPECT_NEAR(s[3].dt_s, 0.1, 1e-9);  // and the log's steps count again from the new clock
  for (std::size_t k = 1; k < s.size(); ++k) EXPECT_GT(s[k].output_stamp_s, s[k - 1].output_stamp_s);
  // Across the jump the odometry is judged over unusable_step_span_s (0.5 s: 5.1 m), not 0.1 s.
  EXPECT_TRUE(p.plausible({2.0, 0.0, 0.0}, s[2]));
  EXPECT_FALSE(p.plausible({2.0, 0.0, 0.0}, s[3]));
}

TEST(StampPolicy, NothingChangesUntilAccepted) {
  StampPolicy p;
  run(p, {0.0, 0.1});
  const StampStep skipped = p.next(0.2);  // a scan the run could not use
  (void)skipped;
  const StampStep s = p.next(0.3);
  EXPECT_NEAR(s.dt_s, 0.2, 1e-12);  // measured from the last accepted scan
}

TEST(StampPolicy, OdometryIncrementsBeyondTheSpeedLimitsAreJumps) {
  StampPolicyParams params;
  params.max_speed_mps = 2.0;
  params.max_turn_rate_radps = 1.0;
  params.jump_margin = 0.0;
  StampPolicy p(params);
  const auto s = run(p, {0.0, 0.5});
  EXPECT_TRUE(p.plausible({0.9, 0.0, 0.1}, s[1]));
  EXPECT_FALSE(p.plausible({1.1, 0.0, 0.1}, s[1]));
  EXPECT_FALSE(p.plausible({0.1, 0.0, 0.6}, s[1]));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(p.plausible({nan, 0.0, 0.0}, s[1]));
  EXPECT_FALSE(p.plausible({0.0, 0.0, nan}, s[1]));
}

TEST(StampPolicy, InvalidParametersNameTheirKey) {
  StampPolicyParams params;
  params.max_time_gap_s = -1.0;
  try {
    StampPolicy p(params);
    FAIL() << "accepted a negative gap";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_time_gap_s"), std::string::npos);
  }
  params = {};
  params.output_nudge_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(StampPolicy{params}, std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
