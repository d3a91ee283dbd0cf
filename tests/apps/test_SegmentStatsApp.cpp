// The lidarseg-segment app run as a class on the real MRPT dataset.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "lidarseg/apps/SegmentStatsApp.h"

namespace lidarseg::apps {
namespace {
namespace fs = std::filesystem;

const std::string kTelecom =
    std::string(LIDARSEG_MRPT_DATASETS_DIR) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

TEST(SegmentStatsApp, SummarisesEveryLevelOfTheRealLog) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom;
  SegmentStatsOptions o;
  o.input = kTelecom;
  o.config_path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  o.csv_path = std::string(LIDARSEG_TEST_TMP_DIR) + "/segment-stats/telecom.csv";
  const SegmentStatsReport r = SegmentStatsApp(o).run();
  EXPECT_EQ(r.scans, 225u);
  EXPECT_TRUE(r.skipped.empty());
  EXPECT_EQ(r.beams_per_scan, 361u);
  EXPECT_NEAR(r.field_of_view_deg, 180.0, 0.01);
  EXPECT_TRUE(r.levels_never_gain_segments);
  // Fewer, longer segments as the level rises (paper Fig. 4).
  EXPECT_GT(r.levels[0].segments_per_scan.mean, r.levels[3].segments_per_scan.mean);
  EXPECT_LT(r.levels[0].segment_length_m.mean, r.levels[3].segment_length_m.mean);
  EXPECT_GE(r.levels[1].point_coverage, r.levels[3].point_coverage - 1e-12);
  EXPECT_GT(r.levels[3].point_coverage, 0.3);
  EXPECT_EQ(r.total_us.count, 225u);

  std::ifstream csv(o.csv_path);
  std::string line;
  std::size_t lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 226u);  // header + one row per scan

  std::ostringstream printed;
  SegmentStatsApp::print(r, printed);
  EXPECT_NE(printed.str().find("fused-again"), std::string::npos);
  EXPECT_NE(printed.str().find("scans: 225"), std::string::npos);
  std::ostringstream warned;
  SegmentStatsApp::printWarnings(r, warned);
  EXPECT_EQ(warned.str(), "");  // nothing skipped, nothing said
}

TEST(SegmentStatsApp, SkippedScansAreAWarningOnStderrNotInTheResults) {
  SegmentStatsReport r;
  r.input = "log.rawlog";
  r.scans = 3;
  r.skipped = {"log.rawlog: entry 7 (scan 2): no valid beam", "log.rawlog: entry 9 (scan 4): no valid beam"};
  r.skipped_count = 2;
  std::ostringstream out, err;
  SegmentStatsApp::print(r, out);
  SegmentStatsApp::printWarnings(r, err);
  EXPECT_EQ(out.str().find("entry 7"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("scans: 3"), std::string::npos);
  EXPECT_EQ(err.str(), "lidarseg-segment: warning: 2 scans or lines skipped, the first: log.rawlog: entry 7 (scan 2): no valid beam\n");
}

TEST(SegmentStatsApp, MaxScansAndErrors) {
  if (!fs::exists(kTelecom)) GTEST_SKIP() << "missing " << kTelecom;
  SegmentStatsOptions o;
  o.input = kTelecom;
  o.max_scans = 10;
  EXPECT_EQ(SegmentStatsApp(o).run().scans, 10u);
  o.sensor_label = "NO_SUCH_LASER";
  EXPECT_THROW(SegmentStatsApp(o).run(), std::runtime_error);
  o.sensor_label.clear();
  o.config_path = "/nonexistent/config.ini";
  EXPECT_THROW(SegmentStatsApp(o).run(), std::runtime_error);
}

// A segment of coincident points (5 beams over 4e-9 rad at 2 m) has an infinite covariance
// (no direction); its θ sigma made the level's median "-nan" (issue 16). It is left out of
// the median and counted.
TEST(SegmentStatsApp, ASegmentOfPointsAtOnePlaceIsCountedNotANaNMedian) {
  const std::string dir = std::string(LIDARSEG_TEST_TMP_DIR) + "/segment-stats";
  fs::create_directories(dir);
  SegmentStatsOptions o;
  o.input = dir + "/coincident.log";
  std::ofstream log(o.input);
  for (int k = 0; k < 3; ++k) {
    log << "ROBOTLASER1 0 0 0.000000004 0.000000001 30 0.01 0 5 2.0 2.0 2.0 2.0 2.0 0 0 0 0 0 0 0 0 0 0.5 0.5 0 "
        << 100 + k << ".0 host " << 100 + k << ".0\n";
  }
  log.close();
  const SegmentStatsReport r = SegmentStatsApp(o).run();
  ASSERT_EQ(r.scans, 3u);
  EXPECT_EQ(r.levels[0].segments_without_direction, 3u);
  EXPECT_TRUE(std::isfinite(r.levels[0].median_theta_sigma_rad));
  std::ostringstream out;
  SegmentStatsApp::print(r, out);
  EXPECT_EQ(out.str().find("nan"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("segments of points at one place (no direction, left out of sigma theta): level 0: 3, level 1: 3"),
            std::string::npos)
      << out.str();
}

}  // namespace
}  // namespace lidarseg::apps
