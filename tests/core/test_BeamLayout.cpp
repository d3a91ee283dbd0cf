#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/BeamLayout.h"

namespace lidarseg {
namespace {

TEST(BeamLayout, CentredCoversTheFieldOfViewInclusive) {
  const BeamLayout l = BeamLayout::centred(541, 270.0 * kPi / 180.0);
  ASSERT_EQ(l.size(), 541u);
  EXPECT_NEAR(l.angle(0), -135.0 * kPi / 180.0, 1e-12);
  EXPECT_NEAR(l.angle(540), 135.0 * kPi / 180.0, 1e-12);
  EXPECT_NEAR(l.angle(270), 0.0, 1e-12);
  EXPECT_NEAR(l.meanIncrement(), 0.5 * kPi / 180.0, 1e-12);
  EXPECT_FALSE(l.wrapsAround());
}

TEST(BeamLayout, PrecomputesCosineAndSine) {
  const BeamLayout l = BeamLayout::uniform(7, -1.0, 0.3);
  for (std::size_t i = 0; i < l.size(); ++i) {
    EXPECT_DOUBLE_EQ(l.cosine(i), std::cos(-1.0 + 0.3 * static_cast<double>(i)));
    EXPECT_DOUBLE_EQ(l.sine(i), std::sin(-1.0 + 0.3 * static_cast<double>(i)));
  }
}

TEST(BeamLayout, FullTurnWrapsAroundInBothDirections) {
  EXPECT_TRUE(BeamLayout::uniform(360, -kPi, 2 * kPi / 360).wrapsAround());
  EXPECT_TRUE(BeamLayout::uniform(720, kPi, -2 * kPi / 720).wrapsAround());
  // 359 degrees of a 1-degree sensor minus one beam is not a full turn.
  EXPECT_FALSE(BeamLayout::uniform(358, -kPi, 2 * kPi / 360).wrapsAround());
}

TEST(BeamLayout, DegenerateSizes) {
  EXPECT_TRUE(BeamLayout::centred(0, 1.0).empty());
  const BeamLayout one = BeamLayout::centred(1, 1.0);
  EXPECT_EQ(one.size(), 1u);
  EXPECT_EQ(one.meanIncrement(), 0.0);
  EXPECT_FALSE(one.wrapsAround());
}

TEST(BeamLayout, RejectsNonFiniteAngles) {
  EXPECT_THROW(BeamLayout({0.0, std::nan("")}), std::invalid_argument);
  EXPECT_THROW(BeamLayout::uniform(3, 0.0, INFINITY), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg
