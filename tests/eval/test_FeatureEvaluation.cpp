#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "lidarseg/eval/FeatureEvaluation.h"

namespace lidarseg::eval {
namespace {

TrueFeature truth(FeatureType t, double x, double y, bool resolvable = true) {
  TrueFeature f;
  f.type = t;
  f.seen_as = t;
  f.position = {x, y};
  f.resolvable = resolvable;
  return f;
}

Feature detected(FeatureType t, double x, double y) {
  Feature f;
  f.type = t;
  f.position = {x, y};
  return f;
}

TEST(FeatureEvaluation, CountsRecallAndPrecisionPerTypeWithinTheGate) {
  FeatureEvaluation ev(0.2);
  const auto errs = ev.add(
      {truth(FeatureType::kDoorOpen, 1, 0), truth(FeatureType::kDoorClosed, 3, 0),
       truth(FeatureType::kCornerConcave, 5, 5), truth(FeatureType::kCornerConvex, 9, 9, false)},
      {detected(FeatureType::kDoorOpen, 1.1, 0),        // right
       detected(FeatureType::kDoorOpen, 3.05, 0),       // a door, wrong type
       detected(FeatureType::kCornerConcave, 5.5, 5),   // outside the gate
       detected(FeatureType::kCornerConvex, 9, 9.1)});  // right, of an unresolvable truth
  ASSERT_EQ(errs.size(), 3u);
  EXPECT_EQ(ev.doors().truths, 2u);
  EXPECT_EQ(ev.doors().truths_found, 2u);  // both doors found as doors
  EXPECT_EQ(ev.doors().detections_right, 2u);
  const auto& open = ev.byType()[static_cast<std::size_t>(FeatureType::kDoorOpen)];
  EXPECT_EQ(open.truths, 1u);
  EXPECT_EQ(open.truths_found, 1u);
  EXPECT_EQ(open.detections, 2u);
  EXPECT_EQ(open.detections_right, 1u);
  EXPECT_DOUBLE_EQ(open.precision(), 0.5);
  const auto& closed = ev.byType()[static_cast<std::size_t>(FeatureType::kDoorClosed)];
  EXPECT_EQ(closed.truths_found, 0u);
  EXPECT_DOUBLE_EQ(closed.recall(), 0.0);
  EXPECT_TRUE(std::isnan(closed.precision()));  // none detected
  // Corners: the unresolvable truth is not counted for recall, but makes its detection right.
  EXPECT_EQ(ev.corners().truths, 1u);
  EXPECT_EQ(ev.corners().truths_found, 0u);
  EXPECT_EQ(ev.corners().detections, 2u);
  EXPECT_EQ(ev.corners().detections_right, 1u);
  EXPECT_EQ(ev.corners().visible, 2u);
  EXPECT_EQ(ev.corners().visible_found, 1u);
  EXPECT_EQ(ev.confusion()[static_cast<std::size_t>(FeatureType::kDoorClosed)]
                          [static_cast<std::size_t>(FeatureType::kDoorOpen)],
            1u);
}

TEST(FeatureEvaluation, ATJunctionsTwoCornersAreMatchedByType) {
  // Two true corners at one point (a T): the concave detection goes to the concave truth
  // even though the convex truth is listed first.
  FeatureEvaluation ev(0.2);
  ev.add({truth(FeatureType::kCornerConvex, 1, 1, false), truth(FeatureType::kCornerConcave, 1, 1)},
         {detected(FeatureType::kCornerConcave, 1.01, 1)});
  EXPECT_EQ(ev.byType()[static_cast<std::size_t>(FeatureType::kCornerConcave)].truths_found, 1u);
  EXPECT_EQ(ev.byType()[static_cast<std::size_t>(FeatureType::kCornerConcave)].detections_right, 1u);
}

TEST(FeatureEvaluation, ADoorAjarSeenAsOpenAcceptsEither) {
  FeatureEvaluation ev(0.2);
  TrueFeature t = truth(FeatureType::kDoorAjar, 0, 2);
  t.seen_as = FeatureType::kDoorOpen;
  ev.add({t}, {detected(FeatureType::kDoorOpen, 0, 2)});
  EXPECT_EQ(ev.byType()[static_cast<std::size_t>(FeatureType::kDoorOpen)].truths_found, 1u);
  EXPECT_THROW(FeatureEvaluation(0.0), std::invalid_argument);
}

TEST(FeatureEvaluation, ReadsTheSimulatorsFileAndNamesBadLines) {
  const std::string dir = LIDARSEG_TEST_TMP_DIR;
  const std::string good = dir + "/truth_good.csv";
  std::ofstream(good) << "scan,t,type,x,y,theta,width,id,resolvable,seen_as\n"
                      << "0,1.0,door_ajar,1,2,0,0.9,3,1,door_open\n"
                      << "0,1.0,corner_convex,4,5,0,0,1,0,corner_convex\n"
                      << "2,1.1,door_closed,1,2,0,0.9,4,1,door_closed\n";
  const auto t = readTrueFeatures(good);
  ASSERT_EQ(t.size(), 2u);
  ASSERT_EQ(t.at(0).size(), 2u);
  EXPECT_EQ(t.at(0)[0].type, FeatureType::kDoorAjar);
  EXPECT_EQ(t.at(0)[0].seen_as, FeatureType::kDoorOpen);
  EXPECT_FALSE(t.at(0)[1].resolvable);
  EXPECT_DOUBLE_EQ(t.at(2)[0].position.x(), 1.0);
  const std::string bad = dir + "/truth_bad.csv";
  std::ofstream(bad) << "scan,t,type,x,y,theta,width,id\n0,1.0,door_open,1,2,0,0.9,3\n0,1.0,window,1,2,0,0.9,3\n";
  try {
    readTrueFeatures(bad);
    FAIL() << "accepted an unknown type";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("truth_bad.csv:3"), std::string::npos) << m;
    EXPECT_NE(m.find("window"), std::string::npos) << m;
  }
  std::ofstream(bad) << "scan,t,type,x,y,theta,width,id\n0,1.0,door_open,1,nan,0,0.9,3\n";
  EXPECT_THROW(readTrueFeatures(bad), std::runtime_error);
  EXPECT_THROW(readTrueFeatures(dir + "/no_such_truth.csv"), std::runtime_error);
}

// Issue 16: 1e300 in a truth x reached the --matches-out table as a 300-digit number that cut
// its row at 256 characters; a row given twice doubled the truths (recall halved); another
// file's header was read as data. Each is refused with the file, line and column.
TEST(FeatureEvaluation, TruthValuesOutOfBoundsRowsGivenTwiceAndOtherFilesAreRefused) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/truth_checked.csv";
  const auto errorFor = [&](const std::string& rows) {
    std::ofstream(path) << "scan,t,type,x,y,theta,width,id,resolvable,seen_as\n" << rows;
    try {
      readTrueFeatures(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).substr(path.size());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1e300,2,0,0.9,3,1,door_open\n"), ":2: column 'x' = 1e300 is not in [-1e6, 1e6]");
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1,2,0,1e300,3,1,door_open\n"), ":2: column 'width' = 1e300 is not in [0, 1e6]");
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1,2,0,-5,3,1,door_open\n"), ":2: column 'width' = -5 is not in [0, 1e6]");
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1,2,0,0.9,3,7,door_open\n"), ":2: column 'resolvable' must be 0 or 1, not '7'");
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1,2,0,0.9,3,1,door_open\n0,1.0,door_closed,1,2,0,0.9,3,1,door_closed\n"),
            ":3: door 3 of scan 0 given twice (first at line 2)");
  // Doors and corners are numbered apart; the same number in another scan is another sighting.
  EXPECT_EQ(errorFor("0,1.0,door_ajar,1,2,0,0.9,3,1,door_open\n0,1.0,corner_convex,1,2,0,0,3,0,corner_convex\n"
                     "1,1.1,door_ajar,1,2,0,0.9,3,1,door_open\n"),
            "no error");
  std::ofstream(path) << "t,type,x,y,theta\n1.0,door_open,1,2,0\n";
  try {
    readTrueFeatures(path);
    FAIL() << "another file's header read as data";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":1: not a feature truth file: its header starts 't'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace lidarseg::eval
