// The one palette of the charts and the inspector: a reference trajectory's colour follows
// one rule, wherever it is drawn.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lidarseg/report/Palette.h"

namespace lidarseg::report {
namespace {

bool same(const Rgb& a, const Rgb& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

TEST(Palette, ReferencesAreColouredByKindThenInTurn) {
  const std::vector<std::string> names = {"ground truth", "mine", "icp-run", "gt", "theirs", "MRPT ICP", "third"};
  const std::vector<Rgb> colours = referenceColours(names);
  ASSERT_EQ(colours.size(), names.size());
  EXPECT_TRUE(same(colours[0], kTruthColour));
  EXPECT_TRUE(same(colours[1], kOtherColour));  // the first of the others, even after a truth
  EXPECT_TRUE(same(colours[2], kIcpColour));
  EXPECT_TRUE(same(colours[3], kTruthColour));
  EXPECT_TRUE(same(colours[4], kWheelColour));  // the second of the others: apart from the first
  EXPECT_TRUE(same(colours[5], kIcpColour));
  EXPECT_TRUE(same(colours[6], kOtherColour));
  EXPECT_TRUE(referenceColours({}).empty());
}

TEST(Palette, NoReferenceIsDrawnInLidarsegsColour) {
  for (const Rgb& c : referenceColours({"ground truth", "icp", "a", "b"})) EXPECT_FALSE(same(c, kLidarsegColour));
  // The methods' colours are told apart.
  const std::vector<Rgb> methods = {kLidarsegColour, kIcpColour, kIcpS2sColour, kTruthColour, kWheelColour, kOtherColour};
  for (std::size_t i = 0; i < methods.size(); ++i) {
    for (std::size_t j = i + 1; j < methods.size(); ++j) EXPECT_FALSE(same(methods[i], methods[j])) << i << " " << j;
  }
}

TEST(Palette, AScanDrawingsMarksAreToldApart) {
  // Points, doors, corners and the segments (lidarseg's blue) in one drawing: no two alike,
  // and the robot's red apart from the doors' it sits among.
  const std::vector<Rgb> marks = {kScanPointColour, kDoorColour, kCornerColour, kLidarsegColour, kRobotColour};
  for (std::size_t i = 0; i < marks.size(); ++i) {
    for (std::size_t j = i + 1; j < marks.size(); ++j) EXPECT_FALSE(same(marks[i], marks[j])) << i << " " << j;
  }
}

}  // namespace
}  // namespace lidarseg::report
