#include <algorithm>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "lidarseg/mrpt/SimulationConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

// config/simulate.ini documents every [simulation] key with the lms100 defaults.
TEST(SimulationConfig, SimulateIniHasEveryKeyWithTheDefaultValue) {
  const std::string path = std::string(LIDARSEG_CONFIG_DIR) + "/simulate.ini";
  mrpt::config::CConfigFile file(path);
  std::vector<std::string> keys;
  file.getAllKeys(kSimulationSection, keys);
  for (const std::string& key : simulationKeys()) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key << " missing";
  }
  sim::SimulationParams loaded;
  loadSimulationParamsFile(loaded, path);
  mrpt::config::CConfigFileMemory a, b;
  saveSimulationParams(loaded, a);
  saveSimulationParams(sim::SimulationParams{}, b);
  EXPECT_EQ(a.getContent(), b.getContent());
}

TEST(SimulationConfig, RoundTripAndErrors) {
  sim::SimulationParams p;
  p.camera.fx = 600.5;
  p.rolling_shutter = false;
  p.camera_every_scans = 7;
  p.odometry.rotation_per_m = 0.01;
  mrpt::config::CConfigFileMemory saved;
  saveSimulationParams(p, saved);
  mrpt::config::CConfigFileMemory reread(saved.getContent());
  sim::SimulationParams q;
  loadSimulationParams(q, reread);
  EXPECT_EQ(q.camera.fx, 600.5);
  EXPECT_FALSE(q.rolling_shutter);
  EXPECT_EQ(q.camera_every_scans, 7u);
  EXPECT_EQ(q.odometry.rotation_per_m, 0.01);
  mrpt::config::CConfigFileMemory bad("[simulation]\nrolling_shutter = 2\n");
  EXPECT_THROW(loadSimulationParams(q, bad), std::invalid_argument);
  mrpt::config::CConfigFileMemory neg("[simulation]\ncamera_fx = -1\n");
  try {
    loadSimulationParams(q, neg);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera_fx"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
