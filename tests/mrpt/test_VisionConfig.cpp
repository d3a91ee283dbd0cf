#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationImage.h>

#include "lidarseg/mrpt/VisionConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

std::string tmpFile(const std::string& name, const std::string& text) {
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(VisionConfig, ShippedFilesSetEveryKey) {
  const std::string def = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  const VisionConfig d = loadVisionConfigFile(def);
  EXPECT_FALSE(d.camera.has_value()) << "default.ini must not override the logs' own calibration";
  EXPECT_DOUBLE_EQ(d.rois.door_height_m, vision::RoiParams{}.door_height_m);
  EXPECT_DOUBLE_EQ(d.people.roi_margin, vision::PeopleDetectorParams{}.roi_margin);
  const std::string text = fileText(def);
  for (const auto& k : roiKeys()) EXPECT_NE(text.find("\n" + k + " ", text.find("[rois]")), std::string::npos) << k;
  for (const auto& k : peopleKeys()) EXPECT_NE(text.find("\n" + k + " ", text.find("[people]")), std::string::npos) << k;

  const std::string sim = std::string(LIDARSEG_CONFIG_DIR) + "/camera/simulator.ini";
  const VisionConfig s = loadVisionConfigFile(sim);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->width, 640);
  EXPECT_DOUBLE_EQ(s.camera->fx, 554.256);
  EXPECT_DOUBLE_EQ(s.camera->z_m, 0.3);
  const std::string cam_text = fileText(sim);
  for (const auto& k : cameraKeys()) EXPECT_NE(cam_text.find("\n" + k + " "), std::string::npos) << k;
}

TEST(VisionConfig, RoundTripAndErrorsNamingFileLineAndKey) {
  VisionConfig c;
  c.camera = vision::CameraParams{};
  c.camera->width = 1280;
  c.camera->k1 = -0.12;
  c.rois.corner_strip_m = 0.6;
  c.people.win_stride_px = 16;
  mrpt::config::CConfigFileMemory mem;
  saveVisionConfig(c, mem);
  const std::string path = tmpFile("vision_roundtrip.ini", mem.getContent());
  const VisionConfig r = loadVisionConfigFile(path);
  ASSERT_TRUE(r.camera.has_value());
  EXPECT_EQ(r.camera->width, 1280);
  EXPECT_DOUBLE_EQ(r.camera->k1, -0.12);
  EXPECT_DOUBLE_EQ(r.rois.corner_strip_m, 0.6);
  EXPECT_EQ(r.people.win_stride_px, 16);

  const auto expectError = [](const std::string& file, const std::string& needle) {
    try {
      loadVisionConfigFile(file);
      ADD_FAILURE() << file << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectError(tmpFile("vision_fx.ini", "[camera]\nwidth = 640\n\nfx = 0\n"), "vision_fx.ini:4 [camera] fx");
  expectError(tmpFile("vision_unknown.ini", "[people]\nstride = 8\n"), "vision_unknown.ini:2 [people] stride");
  expectError(tmpFile("vision_text.ini", "[rois]\ndoor_height_m = tall\n"), "[rois] door_height_m");
  expectError(tmpFile("vision_stride.ini", "[people]\nwin_stride_px = 12\n"), "[people] win_stride_px");
}

// The calibration an MRPT image observation carries gives the same projection as the same
// camera described in the lidar frame: MRPT's camera pose (z forward, x right, y down, on
// the robot) and the lidar's mounting are composed right.
TEST(VisionConfig, CameraOfAnImageObservationMatchesTheLidarFrameDescription) {
  vision::CameraParams p;
  p.x_m = 0.2, p.y_m = -0.1, p.z_m = 0.25, p.yaw_rad = 0.3;
  const vision::CameraModel expected(p);
  const mrpt::poses::CPose3D lidar_on_robot(0.15, 0.05, 0.4, 0.1, 0, 0);
  // The same camera on the robot: lidar pose composed with the camera's pose in the lidar frame.
  const mrpt::poses::CPose3D camera_in_lidar(p.x_m, p.y_m, p.z_m, p.yaw_rad - M_PI / 2, 0, -M_PI / 2);
  mrpt::obs::CObservationImage obs;
  obs.cameraPose = lidar_on_robot + camera_in_lidar;
  obs.cameraParams.ncols = 640;
  obs.cameraParams.nrows = 480;
  obs.cameraParams.setIntrinsicParamsFromValues(p.fx, p.fy, p.cx, p.cy);
  const vision::CameraModel got = cameraOf(obs, lidar_on_robot);
  for (const Eigen::Vector3d& P : {Eigen::Vector3d(4, 0.5, 0.3), Eigen::Vector3d(3, 2, -0.2), Eigen::Vector3d(6, -1, 1)}) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(expected.project(P, a));
    ASSERT_TRUE(got.project(P, b));
    EXPECT_NEAR(a.x(), b.x(), 1e-6);
    EXPECT_NEAR(a.y(), b.y(), 1e-6);
  }
  obs.cameraParams.setIntrinsicParamsFromValues(0, 0, 0, 0);
  EXPECT_THROW(cameraOf(obs, lidar_on_robot), std::invalid_argument);
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
