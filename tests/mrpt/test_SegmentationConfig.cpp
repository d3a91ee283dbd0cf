#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "TempFiles.h"
#include "lidarseg/mrpt/SegmentationConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

SegmentationParams nonDefaultParams() {
  SegmentationParams p;
  p.noise.range_sigma_m = 0.0234567891234;
  p.noise.bearing_sigma_rad = 0.001;
  p.wall_danielsson.threshold_m = 0.0311;
  p.wall_danielsson.max_range_jump_m = 0.45;
  p.wall_danielsson.max_range_jump_ratio = 0.07;
  p.wall_danielsson.min_points = 4;
  p.cascade.first_fusion = {0.0612, 0.033, 0.41, 2.5};
  p.cascade.erosion = {0.27, 6};
  p.cascade.second_fusion = {0.071, 0.061, 0.93, 0.0};
  return p;
}

void expectEqual(const SegmentationParams& a, const SegmentationParams& b) {
  EXPECT_EQ(a.noise.range_sigma_m, b.noise.range_sigma_m);
  EXPECT_EQ(a.noise.bearing_sigma_rad, b.noise.bearing_sigma_rad);
  EXPECT_EQ(a.wall_danielsson.threshold_m, b.wall_danielsson.threshold_m);
  EXPECT_EQ(a.wall_danielsson.max_range_jump_m, b.wall_danielsson.max_range_jump_m);
  EXPECT_EQ(a.wall_danielsson.max_range_jump_ratio, b.wall_danielsson.max_range_jump_ratio);
  EXPECT_EQ(a.wall_danielsson.min_points, b.wall_danielsson.min_points);
  for (const auto& [x, y] : {std::pair{a.cascade.first_fusion, b.cascade.first_fusion},
                             std::pair{a.cascade.second_fusion, b.cascade.second_fusion}}) {
    EXPECT_EQ(x.max_angle_rad, y.max_angle_rad);
    EXPECT_EQ(x.max_line_distance_m, y.max_line_distance_m);
    EXPECT_EQ(x.max_gap_m, y.max_gap_m);
    EXPECT_EQ(x.noise_gate_sigmas, y.noise_gate_sigmas);
  }
  EXPECT_EQ(a.cascade.erosion.min_length_m, b.cascade.erosion.min_length_m);
  EXPECT_EQ(a.cascade.erosion.min_points, b.cascade.erosion.min_points);
}

using lidarseg::testing::writeTemp;

TEST(SegmentationConfig, IniSaveLoadRoundTripIsExact) {
  const SegmentationParams original = nonDefaultParams();
  mrpt::config::CConfigFileMemory saved;
  saveSegmentationParams(original, saved);
  mrpt::config::CConfigFileMemory reread(saved.getContent());
  SegmentationParams loaded;
  loadSegmentationParams(loaded, reread);
  expectEqual(original, loaded);
}

TEST(SegmentationConfig, YamlRoundTripThroughAFile) {
  const SegmentationParams original = nonDefaultParams();
  mrpt::config::CConfigFileMemory saved;
  saveSegmentationParams(original, saved, "seg");
  const std::string path = writeTemp("roundtrip.yaml", saved.getContentAsYAML());
  expectEqual(original, loadSegmentationParamsFile(path, "seg"));
}

TEST(SegmentationConfig, AbsentKeysKeepDefaults) {
  mrpt::config::CConfigFileMemory cfg("[segmentation]\nwd_threshold_m = 0.05\n");
  SegmentationParams p;
  loadSegmentationParams(p, cfg);
  EXPECT_EQ(p.wall_danielsson.threshold_m, 0.05);
  EXPECT_EQ(p.cascade.erosion.min_length_m, SegmentationParams{}.cascade.erosion.min_length_m);
}

// config/default.ini documents every key, with the library's default values.
TEST(SegmentationConfig, DefaultIniHasEveryKeyWithTheDefaultValue) {
  const std::string path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  mrpt::config::CConfigFile file(path);
  std::vector<std::string> keys;
  file.getAllKeys(kSegmentationSection, keys);
  for (const std::string& key : segmentationKeys()) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key << " missing";
  }
  expectEqual(loadSegmentationParamsFile(path), SegmentationParams{});
}

std::string errorOf(const std::string& name, const std::string& text) {
  try {
    loadSegmentationParamsFile(writeTemp(name, text));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(SegmentationConfig, ErrorsNameFileLineSectionAndKey) {
  const std::string unknown =
      errorOf("unknown.ini", "[segmentation]\nwd_threshold_m = 0.02\nwd_treshold_m = 0.03\n");
  EXPECT_NE(unknown.find("unknown.ini:3 [segmentation] wd_treshold_m: unknown key"),
            std::string::npos)
      << unknown;
  const std::string nan = errorOf("nan.ini", "[segmentation]\n\nerosion_min_length_m = abc\n");
  EXPECT_NE(nan.find("nan.ini:3 [segmentation] erosion_min_length_m: 'abc' is not a number"),
            std::string::npos)
      << nan;
  const std::string range = errorOf("range.ini", "[segmentation]\nfusion1_max_gap_m = -2\n");
  EXPECT_NE(range.find("range.ini:2 [segmentation] fusion1_max_gap_m"), std::string::npos) << range;
  EXPECT_NE(range.find("got -2"), std::string::npos) << range;
  const std::string count = errorOf("count.ini", "[segmentation]\nwd_min_points = 2.5\n");
  EXPECT_NE(count.find("wd_min_points"), std::string::npos) << count;
  const std::string yaml =
      errorOf("bad.yaml", "segmentation:\n  wd_threshold_m: 0.02\n  wd_min_points: -4\n");
  EXPECT_NE(yaml.find("bad.yaml:3 [segmentation] wd_min_points"), std::string::npos) << yaml;
}

TEST(SegmentationConfig, YamlWithOneKeyAndSectionRules) {
  EXPECT_EQ(loadSegmentationParamsFile(writeTemp("one.yaml", "segmentation:\n  wd_threshold_m: 0.03\n"))
                .wall_danielsson.threshold_m,
            0.03);
  // A misspelt or missing section is an error, not a silent fallback to the defaults.
  EXPECT_EQ(errorOf("nosection.ini", "[segmentaton]\nwd_threshold_m = 0.03\n"),
            std::string(LIDARSEG_TEST_TMP_DIR) + "/nosection.ini: no [segmentation] section");
  EXPECT_NE(errorOf("flat.yaml", "wd_threshold_m: 0.03\n").find("section"), std::string::npos);
  // Section names as MRPT reads them (spaces, case); a key given twice is an error at the
  // second (issue 16: the last used to win silently).
  const std::string dup = errorOf("dup.ini", "[ Segmentation ]\nwd_min_points = 3\nwd_min_points = 1\n");
  EXPECT_NE(dup.find("dup.ini:3 [Segmentation] wd_min_points: given twice (first at line 2)"), std::string::npos)
      << dup;
  const std::string key = errorOf("key.ini", "[ Segmentation ]\nwd_min_points = 1\n");
  EXPECT_NE(key.find("key.ini:2 [segmentation] wd_min_points"), std::string::npos) << key;
}

TEST(SegmentationConfig, MissingFileIsAClearError) {
  try {
    loadSegmentationParamsFile("/nonexistent/lidarseg.ini");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/lidarseg.ini"), std::string::npos);
  }
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
