#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::vision {
namespace {

// Pedestrians in a hall (Debian's opencv-doc, installed by run.sh).
const std::string kVideo = "/usr/share/doc/opencv-doc/examples/data/vtest.avi";

cv::Mat frameOfVideo(int index) {
  cv::VideoCapture cap(kVideo);
  cv::Mat f;
  for (int i = 0; i <= index; ++i) {
    if (!cap.read(f)) return {};
  }
  return f;
}

TEST(PeopleDetector, ParametersAreValidated) {
  PeopleDetectorParams p;
  p.win_stride_px = 12;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = {};
  p.scale_step = 1.0;
  EXPECT_THROW(PeopleDetector{p}, std::invalid_argument);
  p = {};
  p.roi_margin = -0.1;
  try {
    p.validate();
    FAIL() << "negative margin accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("roi_margin", 0), 0u) << e.what();
  }
  p.roi_margin = 1e9;  // it overflowed an int in grow(): a smaller, arbitrary region (issue 16)
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

// A region grown by a margin stays the region grown and clipped to the frame, however large
// the margin (computed in floating point: 1e9 overflowed an int).
TEST(PeopleDetector, AGrownRegionIsClippedToTheFrame) {
  const cv::Size frame(640, 480);
  EXPECT_EQ(grow(cv::Rect(100, 100, 100, 200), 0.25, frame), cv::Rect(75, 50, 150, 300));
  EXPECT_EQ(grow(cv::Rect(100, 100, 100, 200), 10.0, frame), cv::Rect(0, 0, 640, 480));
  EXPECT_EQ(grow(cv::Rect(100, 100, 100, 200), 1e9, frame), cv::Rect(0, 0, 640, 480));
  EXPECT_EQ(grow(cv::Rect(600, 400, 100, 100), 0.0, frame), cv::Rect(600, 400, 40, 80));
}

// The resized image obeys the images' own 8192 px cap (a scale of 4 on an 8192 px image
// asked for 16 GB).
TEST(PeopleDetector, AScaleBeyondTheImageCapIsRefused) {
  PeopleDetectorParams p;
  p.image_scale = 4.0;
  const PeopleDetector d(p);
  const cv::Mat big(3000, 100, CV_8UC3, cv::Scalar(0, 0, 0));
  try {
    d.detectFullFrame(big);
    FAIL() << "a 12000 px image was made";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("image_scale 4 makes this 100x3000 image 12000 px"), std::string::npos)
        << e.what();
  }
  const cv::Mat small(200, 100, CV_8UC3, cv::Scalar(0, 0, 0));
  EXPECT_NO_THROW(d.detectFullFrame(small));
}

TEST(PeopleDetector, OverlappingRegionsAreMergedUntilDisjoint) {
  // a overlaps b, b overlaps c (a and c do not): one box; d stays apart.
  const auto merged = mergeOverlapping({cv::Rect(0, 0, 10, 10), cv::Rect(8, 0, 10, 10), cv::Rect(16, 5, 10, 10),
                                        cv::Rect(100, 100, 5, 5)});
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0], cv::Rect(0, 0, 26, 15));
  EXPECT_EQ(merged[1], cv::Rect(100, 100, 5, 5));
}

TEST(PeopleDetector, AnalysedRegionsHoldAWindowStayInsideAndStartOnTheStrideGrid) {
  const PeopleDetector det;
  const cv::Size image(640, 480);
  // A thin corner strip, a door box at the image's edge, one region outside.
  const auto crops = det.analysedRegions({cv::Rect(101, 203, 10, 30), cv::Rect(600, 10, 40, 300),
                                          cv::Rect(700, 10, 10, 10)},
                                         image);
  ASSERT_EQ(crops.size(), 2u);
  for (const cv::Rect& c : crops) {
    EXPECT_GE(c.width, 64);
    EXPECT_GE(c.height, 128);
    EXPECT_EQ(c & cv::Rect(cv::Point(0, 0), image), c);
    EXPECT_EQ(c.x % 8, 0);
    EXPECT_EQ(c.y % 8, 0);
  }
  // Each region lies inside its crop.
  EXPECT_EQ(crops[0] & cv::Rect(101, 203, 10, 30), cv::Rect(101, 203, 10, 30));
  EXPECT_EQ(crops[1] & cv::Rect(600, 10, 40, 300), cv::Rect(600, 10, 40, 300));
}

// On real pedestrians: a person found on the whole frame is found again when only a region
// around it is analysed, and nobody is found in a region of lawn; the share of the image
// analysed is the crops' area.
TEST(PeopleDetector, PeopleInsideTheRegionsAreStillFoundOnARealVideo) {
  ASSERT_TRUE(std::filesystem::exists(kVideo)) << kVideo << " missing: run ./run.sh deps (package opencv-doc)";
  const cv::Mat frame = frameOfVideo(200);
  ASSERT_FALSE(frame.empty());
  const PeopleDetector det;
  const PeopleDetection full = det.detectFullFrame(frame);
  EXPECT_DOUBLE_EQ(full.analysed_fraction, 1.0);
  ASSERT_GE(full.people.size(), 1u) << "HOG found nobody on frame 200";
  for (const Person& target : full.people) {
    const PeopleDetection inside = det.detectInRegions(frame, {target.box});
    double best = 0;
    for (const Person& p : inside.people) best = std::max(best, intersectionOverUnion(p.box, target.box));
    EXPECT_GE(best, 0.5) << "person at " << target.box << " lost inside its region";
    double area = 0;
    for (const cv::Rect& c : inside.analysed) area += c.area();
    EXPECT_NEAR(inside.analysed_fraction, area / frame.total(), 1e-12);
    EXPECT_LT(inside.analysed_fraction, 0.25);
  }
  // The lawn in the lower left corner of the hall video: nobody there.
  const PeopleDetection lawn = det.detectInRegions(frame, {cv::Rect(20, 400, 150, 150)});
  EXPECT_TRUE(lawn.people.empty());
  EXPECT_GT(lawn.analysed_fraction, 0.0);
}

}  // namespace
}  // namespace lidarseg::vision
