#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "lidarseg/mrpt/FeatureConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

std::string tmpFile(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(FeatureConfig, TheShippedDefaultFileSetsEveryKeyToTheDefaults) {
  const std::string path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  const FeatureDetectorParams p = loadFeatureDetectorParamsFile(path);
  const FeatureDetectorParams d;
  EXPECT_EQ(p.level, d.level);
  EXPECT_DOUBLE_EQ(p.corner_min_arm_m, d.corner_min_arm_m);
  EXPECT_DOUBLE_EQ(p.door_max_recess_m, d.door_max_recess_m);
  EXPECT_EQ(p.door_max_segments_between, d.door_max_segments_between);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto section = text.find("[features]");
  ASSERT_NE(section, std::string::npos);
  for (const auto& k : featureKeys()) EXPECT_NE(text.find("\n" + k + " ", section), std::string::npos) << k;
}

TEST(FeatureConfig, RoundTripKeepsEveryValue) {
  FeatureDetectorParams p;
  p.level = CascadeLevel::kWallDanielsson;
  p.door_min_width_m = 0.6;
  p.corner_min_points = 7;
  p.door_leaf_parallel_deg = 12.5;
  mrpt::config::CConfigFileMemory cfg;
  saveFeatureDetectorParams(p, cfg);
  FeatureDetectorParams q;
  loadFeatureDetectorParams(q, cfg);
  EXPECT_EQ(q.level, CascadeLevel::kWallDanielsson);
  EXPECT_DOUBLE_EQ(q.door_min_width_m, 0.6);
  EXPECT_EQ(q.corner_min_points, 7u);
  EXPECT_DOUBLE_EQ(q.door_leaf_parallel_deg, 12.5);
}

TEST(FeatureConfig, BadValuesAndUnknownKeysNameFileLineAndKey) {
  const auto bad = tmpFile("features_bad.ini", "[features]\ndoor_min_width_m = 0.7\ndoor_max_width_m = 0.5\n");
  try {
    loadFeatureDetectorParamsFile(bad);
    FAIL() << "accepted door_max_width_m < door_min_width_m";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("door_max_width_m"), std::string::npos) << e.what();
  }
  const auto unknown = tmpFile("features_unknown.ini", "[features]\n\ndoor_width = 1\n");
  try {
    loadFeatureDetectorParamsFile(unknown);
    FAIL() << "accepted an unknown key";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("door_width"), std::string::npos) << m;
    EXPECT_NE(m.find("features_unknown.ini:3"), std::string::npos) << m;
  }
  // A file without the section: the defaults.
  const auto none = tmpFile("features_none.ini", "[segmentation]\nwd_threshold_m = 0.02\n");
  EXPECT_DOUBLE_EQ(loadFeatureDetectorParamsFile(none).door_max_width_m, FeatureDetectorParams{}.door_max_width_m);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
