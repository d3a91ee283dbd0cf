#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "TempFiles.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/OdometryConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::writeTemp;

std::string errorOf(const std::string& path) {
  try {
    LidarsegConfig::loadFile(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(LidarsegConfig, TheShippedDefaultFileLoadsWithEveryStampKey) {
  const std::string path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  const LidarsegConfig c = LidarsegConfig::loadFile(path);
  EXPECT_EQ(c.icp.maxIterations, 60u);  // [icp] is read
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const auto& k : stampKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
}

TEST(LidarsegConfig, AMisspeltSectionIsAnErrorNamingFileAndLine) {
  const std::string path = writeTemp("misspelt.ini", "[matcher]\niterations = 4\n\n[matchr]\niterations = 5\n");
  const std::string e = errorOf(path);
  EXPECT_NE(e.find(path + ":4"), std::string::npos) << e;
  EXPECT_NE(e.find("[matchr]"), std::string::npos) << e;
}

TEST(LidarsegConfig, IcpAndStampsAreReadFromYamlAsFromIni) {
  const std::string yaml =
      writeTemp("run.yaml", "icp:\n  maxIterations: 17\nstamps:\n  max_time_gap_s: 2.5\nodometry:\n  keyframe_distance_m: 0.2\n");
  const LidarsegConfig c = LidarsegConfig::loadFile(yaml);
  EXPECT_EQ(c.icp.maxIterations, 17u);
  EXPECT_DOUBLE_EQ(c.stamps.max_time_gap_s, 2.5);
  EXPECT_DOUBLE_EQ(c.odometry.keyframe_distance_m, 0.2);
}

TEST(LidarsegConfig, ABadStampValueNamesItsKeyAndLine) {
  const std::string path = writeTemp("stamps.ini", "[stamps]\nmax_speed_mps = -3\n");
  const std::string e = errorOf(path);
  EXPECT_NE(e.find("max_speed_mps"), std::string::npos) << e;
  EXPECT_NE(e.find(":2"), std::string::npos) << e;
}

TEST(LidarsegConfig, SizesAreCappedBeforeAnyParserRuns) {
  EXPECT_NE(errorOf("/dev/zero").find("larger than"), std::string::npos) << errorOf("/dev/zero");
  EXPECT_NE(errorOf(LIDARSEG_TEST_TMP_DIR).find("is a directory"), std::string::npos);
  const std::string deep = writeTemp("deep.yaml", "odometry:\n  level: " + std::string(20000, '[') + "\n");
  const std::string e = errorOf(deep);
  EXPECT_NE(e.find(deep + ":2: YAML nested deeper than"), std::string::npos) << e;
  std::string indented = "odometry:\n";
  for (int k = 1; k < 200; ++k) indented += std::string(2 * static_cast<std::size_t>(k), ' ') + "k" + std::to_string(k) + ":\n";
  EXPECT_NE(errorOf(writeTemp("indented.yaml", indented)).find("nested deeper"), std::string::npos);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
