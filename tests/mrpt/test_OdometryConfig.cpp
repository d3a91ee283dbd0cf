#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "TempFiles.h"
#include "lidarseg/mrpt/OdometryConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::writeTemp;

TEST(OdometryConfig, TheShippedDefaultFileSetsEveryKeyToTheDefaults) {
  const OdometryParams p = loadOdometryParamsFile(std::string(LIDARSEG_CONFIG_DIR) + "/default.ini");
  const OdometryParams d;
  EXPECT_DOUBLE_EQ(p.matcher.cog_gate_m, d.matcher.cog_gate_m);
  EXPECT_EQ(p.matcher.band_half_width, d.matcher.band_half_width);
  EXPECT_DOUBLE_EQ(p.keyframe_distance_m, d.keyframe_distance_m);
  EXPECT_EQ(p.level, d.level);
  // Every key is written in the file (a user sees them all).
  std::ifstream in(std::string(LIDARSEG_CONFIG_DIR) + "/default.ini");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const auto& k : matcherKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
  for (const auto& k : odometryKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
  for (const auto& k : refinerKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
  for (const auto& k : searchKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
  EXPECT_DOUBLE_EQ(p.refiner.robust_scale_m, d.refiner.robust_scale_m);
  EXPECT_EQ(p.refiner.level, d.refiner.level);
  EXPECT_DOUBLE_EQ(p.search.linear_window_m, d.search.linear_window_m);
}

// A saved value is the shortest text that reads back as the same double: what a user typed
// (0.3), not 0.29999999999999999; a value that is not 0.3 keeps the digits that tell it.
TEST(OdometryConfig, ValuesAreSavedAsTheShortestTextThatReadsBack) {
  OdometryParams p;
  p.keyframe_distance_m = 0.3;
  p.keyframe_angle_rad = 0.1 + 0.2;
  mrpt::config::CConfigFileMemory cfg;
  saveOdometryParams(p, cfg);
  EXPECT_EQ(cfg.read_string("odometry", "keyframe_distance_m", ""), "0.3");
  EXPECT_EQ(cfg.read_string("odometry", "keyframe_angle_rad", ""), "0.30000000000000004");
}

TEST(OdometryConfig, RoundTripKeepsEveryValue) {
  OdometryParams p;
  p.matcher.cog_gate_m = 1.7;
  p.matcher.iterations = 5;
  p.keyframe_angle_rad = 0.33;
  p.level = CascadeLevel::kFused;
  p.deskew = false;
  p.scanner_rotation_hz = 75.0;
  mrpt::config::CConfigFileMemory cfg;
  saveOdometryParams(p, cfg);
  OdometryParams q;
  loadOdometryParams(q, cfg);
  EXPECT_DOUBLE_EQ(q.matcher.cog_gate_m, 1.7);
  EXPECT_EQ(q.matcher.iterations, 5u);
  EXPECT_DOUBLE_EQ(q.keyframe_angle_rad, 0.33);
  EXPECT_EQ(q.level, CascadeLevel::kFused);
  EXPECT_FALSE(q.deskew);
  EXPECT_DOUBLE_EQ(q.scanner_rotation_hz, 75.0);
}

TEST(OdometryConfig, ErrorsNameFileLineSectionAndKey) {
  const std::string p1 = writeTemp("odo_bad1.ini", "[matcher]\ncog_gate_m = 1\nband_halfwidth = 3\n");
  try {
    loadOdometryParamsFile(p1);
    FAIL() << "unknown key accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("odo_bad1.ini:3"), std::string::npos) << m;
    EXPECT_NE(m.find("band_halfwidth"), std::string::npos) << m;
  }
  const std::string p2 = writeTemp("odo_bad2.ini", "[odometry]\n\nlevel = 9\n");
  try {
    loadOdometryParamsFile(p2);
    FAIL() << "level 9 accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("odo_bad2.ini:3"), std::string::npos) << m;
    EXPECT_NE(m.find("[odometry] level"), std::string::npos) << m;
  }
  const std::string p3 = writeTemp("odo_bad3.ini", "[matcher]\nmax_weight = -1\n");
  EXPECT_THROW(loadOdometryParamsFile(p3), std::invalid_argument);
  const std::string p4 = writeTemp("odo_bad4.ini", "[matcher]\nmax_weight = abc\n");
  EXPECT_THROW(loadOdometryParamsFile(p4), std::invalid_argument);
}

TEST(OdometryConfig, YamlWorksToo) {
  const std::string p = writeTemp("odo.yaml", "matcher:\n  cog_gate_m: 2.5\nodometry:\n  keyframe_distance_m: 0\n");
  const OdometryParams q = loadOdometryParamsFile(p);
  EXPECT_DOUBLE_EQ(q.matcher.cog_gate_m, 2.5);
  EXPECT_DOUBLE_EQ(q.keyframe_distance_m, 0.0);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter

namespace lidarseg::mrpt_adapter {
namespace {

TEST(OdometryConfigEnums, LevelsAndStampsAreReadByNameOrNumberAndWrittenByName) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/enums.ini";
  std::ofstream(path) << "[odometry]\nlevel = fused-again\ndegenerate_fallback_level = 0\nscan_stamp = Middle\n"
                         "[refiner]\nlevel = eroded\n";
  const OdometryParams p = loadOdometryParamsFile(path);
  EXPECT_EQ(p.level, CascadeLevel::kFusedAgain);
  EXPECT_EQ(p.degenerate_fallback_level, CascadeLevel::kWallDanielsson);
  EXPECT_EQ(p.scan_stamp, ScanStamp::kMiddle);
  EXPECT_EQ(p.refiner.level, CascadeLevel::kEroded);
  mrpt::config::CConfigFileMemory cfg;
  saveOdometryParams(p, cfg);
  EXPECT_EQ(cfg.read_string("odometry", "level", ""), "fused_again");
  EXPECT_EQ(cfg.read_string("odometry", "scan_stamp", ""), "middle");
}

TEST(OdometryConfigEnums, AnUnknownNameIsAnErrorListingTheNames) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/bad_enum.ini";
  std::ofstream(path) << "[odometry]\nkeyframe_distance_m = 1\nlevel = fusd\n";
  try {
    loadOdometryParamsFile(path);
    FAIL() << "accepted 'fusd'";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ":3 [odometry] level"), std::string::npos) << m;
    EXPECT_NE(m.find("fused_again"), std::string::npos) << m;
  }
  std::ofstream(path) << "[odometry]\nlevel = 4\n";
  EXPECT_THROW(loadOdometryParamsFile(path), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
