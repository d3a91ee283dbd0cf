#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationImage.h>
#include <opencv2/core.hpp>

#include "lidarseg/apps/SimulateApp.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/CameraRois.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/sim/CameraSimulator.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::vision {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> c;
  std::stringstream ss(line);
  for (std::string s; std::getline(ss, s, ',');) c.push_back(s);
  return c;
}

// The simulator's default camera (0.6 m above the floor) seen from its lidar (0.3 m).
CameraParams simulatorCamera() {
  const sim::PinholeCamera c;
  CameraParams p;
  p.width = c.width, p.height = c.height, p.fx = c.fx, p.fy = c.fy, p.cx = c.cx, p.cy = c.cy;
  p.x_m = c.x_m, p.y_m = c.y_m, p.z_m = c.z_m - 0.3, p.yaw_rad = c.yaw_rad;
  return p;
}

TEST(CameraModel, AgreesWithThePinholeOfTheSimulatorAndRejectsPointsBehind) {
  const sim::World world;
  sim::PinholeCamera pin;
  pin.yaw_rad = 0.2;
  const sim::CameraSimulator sim_cam(world, pin);
  CameraParams p = simulatorCamera();
  p.yaw_rad = 0.2;
  const CameraModel cam(p);
  for (const Eigen::Vector3d& P : {Eigen::Vector3d(3, 0.5, 0.2), Eigen::Vector3d(5, -1, 1.5), Eigen::Vector3d(2, 1, -0.3)}) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(cam.project(P, a));
    ASSERT_TRUE(sim_cam.project(P + Eigen::Vector3d(0, 0, 0.3), b));  // robot frame: z from the floor
    EXPECT_NEAR(a.x(), b.x(), 1e-6);
    EXPECT_NEAR(a.y(), b.y(), 1e-6);
  }
  Eigen::Vector2d px;
  EXPECT_FALSE(cam.project({-2, 0, 0}, px));
  // Barrel distortion pulls an off-axis point towards the centre.
  CameraParams d = simulatorCamera();
  d.k1 = -0.2;
  Eigen::Vector2d undistorted, distorted;
  ASSERT_TRUE(CameraModel(simulatorCamera()).project({2, 1, 0}, undistorted));
  ASSERT_TRUE(CameraModel(d).project({2, 1, 0}, distorted));
  EXPECT_LT(std::abs(distorted.x() - d.cx), std::abs(undistorted.x() - d.cx));
  // Pitching the camera down moves a point ahead up in the image.
  CameraParams down = simulatorCamera();
  down.pitch_rad = 0.2;
  Eigen::Vector2d level_px, down_px;
  ASSERT_TRUE(CameraModel(simulatorCamera()).project({4, 0, 0}, level_px));
  ASSERT_TRUE(CameraModel(down).project({4, 0, 0}, down_px));
  EXPECT_LT(down_px.y(), level_px.y());
  CameraParams bad = simulatorCamera();
  bad.fx = 0;
  EXPECT_THROW(CameraModel{bad}, std::invalid_argument);
}

TEST(RoiProjector, DoorsBecomeClippedBoxesAndDoorsBehindNone) {
  const RoiProjector proj{CameraModel(simulatorCamera())};
  Feature ahead;
  ahead.type = FeatureType::kDoorOpen;
  ahead.jamb_a = {4, 0.45};
  ahead.jamb_b = {4, -0.45};
  ahead.position = {4, 0};
  Feature behind = ahead;
  behind.jamb_a = {-4, 0.45};
  behind.jamb_b = {-4, -0.45};
  Feature across = ahead;  // one jamb ahead, one behind the camera: clipped at the near plane
  across.jamb_a = {2, 0.5};
  across.jamb_b = {-1, 0.5};
  Feature corner;
  corner.type = FeatureType::kCornerConcave;
  corner.position = {5, -1};
  const auto rois = proj.project({ahead, behind, across, corner});
  ASSERT_EQ(rois.size(), 3u);
  EXPECT_EQ(rois[0].feature, 0u);
  EXPECT_FALSE(rois[0].clipped);
  // A 0.9 m x 2 m doorway 3.9 m in front of the camera: about 128 x 284 pixels.
  EXPECT_NEAR(rois[0].box.width, 0.9 * 554.256 / 3.9, 3);
  EXPECT_NEAR(rois[0].box.height, 2.0 * 554.256 / 3.9, 3);
  EXPECT_EQ(rois[1].feature, 2u);
  EXPECT_TRUE(rois[1].clipped);
  EXPECT_EQ(rois[2].type, FeatureType::kCornerConcave);
  for (const Roi& r : rois) {
    EXPECT_GE(r.box.x, 0);
    EXPECT_GE(r.box.y, 0);
    EXPECT_LE(r.box.x + r.box.width, 640);
    EXPECT_LE(r.box.y + r.box.height, 480);
  }
  EXPECT_NEAR(intersectionOverUnion(cv::Rect(0, 0, 10, 10), cv::Rect(5, 0, 10, 10)), 50.0 / 150.0, 1e-12);
  EXPECT_NEAR(coveredFraction({cv::Rect(0, 0, 10, 10), cv::Rect(5, 0, 10, 10)}, cv::Size(100, 10)), 0.15, 1e-12);
}

// The acceptance check: doors detected by the lidar and projected give the simulator's
// ground-truth door boxes (its rendered camera images) with a mean IoU >= 0.7.
TEST(RoiProjector, DetectedDoorsMatchTheSimulatorsDoorBoxes) {
  const std::string dir = std::string(LIDARSEG_TEST_TMP_DIR) + "/rois";
  fs::create_directories(dir);
  const std::string traj = dir + "/corridor.traj";
  std::ofstream(traj) << "speed 1.0\nturn_radius 0.6\nwaypoint 0 0\nwaypoint 40 0\nwaypoint 41.2 1\nwaypoint 41.2 11\n";
  apps::SimulateOptions o;
  o.world_path = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/hospital.world";
  o.trajectory_path = traj;
  o.seed = 3;
  o.out_prefix = dir + "/hospital";
  o.camera_every_scans = 10;
  apps::SimulateApp(o).run();

  // Doors the lidar can resolve, per scan (features.csv: scan,t,type,x,y,theta,width,id,
  // resolvable,seen_as).
  std::set<std::pair<std::size_t, std::size_t>> resolvable;
  {
    std::ifstream f(o.out_prefix + ".features.csv");
    std::string row;
    std::getline(f, row);
    while (std::getline(f, row)) {
      const auto c = splitCsv(row);
      ASSERT_EQ(c.size(), 10u) << row;
      if (c[2].rfind("door_", 0) == 0 && c[8] == "1") resolvable.emplace(std::stoul(c[0]), std::stoul(c[7]));
    }
  }
  // Ground-truth boxes per scan: image,scan,t,file,door,kind,u_min,v_min,u_max,v_max; only
  // the doors the lidar can resolve from there (the others are measured by lidarseg-features).
  std::map<std::size_t, std::vector<cv::Rect>> truth;
  std::ifstream in(o.out_prefix + ".rois.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto c = splitCsv(line);
    ASSERT_EQ(c.size(), 10u) << line;
    const int u0 = std::stoi(c[6]), v0 = std::stoi(c[7]), u1 = std::stoi(c[8]), v1 = std::stoi(c[9]);
    if (resolvable.count({std::stoul(c[1]), std::stoul(c[4])}) == 0) continue;
    truth[std::stoul(c[1])].emplace_back(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
  }
  ASSERT_GT(truth.size(), 10u);

  const RoiProjector proj{CameraModel(simulatorCamera())};
  const ScanSegmenter segmenter;
  const FeatureDetector detector;
  mrpt_adapter::LaserLogReader reader(o.out_prefix + ".rawlog");
  mrpt_adapter::ScanConverter converter;
  double iou_sum = 0;
  std::size_t boxes = 0, found = 0;
  while (auto rec = reader.next()) {
    const auto it = truth.find(rec->index);
    if (it == truth.end()) continue;
    const auto features = detector.detect(segmenter.process(converter.convert(*rec->observation)));
    const auto rois = proj.project(features);
    for (const cv::Rect& t : it->second) {
      double best = 0;
      for (const Roi& r : rois) {
        if (isDoor(r.type)) best = std::max(best, intersectionOverUnion(t, r.box));
      }
      ++boxes;
      if (best > 0) {
        ++found;
        iou_sum += best;
      }
    }
  }
  ASSERT_GT(boxes, 20u);
  const double recall = static_cast<double>(found) / static_cast<double>(boxes);
  const double mean_iou = iou_sum / static_cast<double>(found);
  std::cout << "door boxes of resolvable doors: " << boxes << ", found " << found << " (" << recall
            << "), mean IoU " << mean_iou << "\n";
  // Measured 0.94 (seed 3): the 4 boxes left are scans where the lidar misses the door
  // (it finds 0.98 of the resolvable doors over whole logs, docs/results.md).
  EXPECT_GE(recall, 0.9) << found << " of " << boxes;
  EXPECT_GE(mean_iou, 0.7) << "mean IoU over " << found << " boxes";
}

// An image embedded in a log is held to the image files' cap before its pixels are copied and
// drawn on (issue 16); the error names the observation (the caller adds the log and entry).
TEST(CameraRois, AnEmbeddedImageBeyondTheCapIsRefusedWithItsLabel) {
  const mrpt_adapter::CameraRois rois("embedded.rawlog", simulatorCamera(), RoiParams{});
  mrpt::obs::CObservationImage obs;
  obs.sensorLabel = "CAMERA";
  obs.image = mrpt::img::CImage(cv::Mat(16, 8200, CV_8UC3, cv::Scalar::all(7)), mrpt::img::DEEP_COPY);
  std::string error = "(no error)";
  try {
    rois.pixels(obs);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("image observation 'CAMERA': embedded image of 8200 x 16 pixels"), std::string::npos) << error;
  EXPECT_NE(error.find("up to 8192 x 8192 pixels"), std::string::npos) << error;
  obs.image = mrpt::img::CImage(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(7)), mrpt::img::DEEP_COPY);
  const cv::Mat pixels = rois.pixels(obs);
  EXPECT_EQ(pixels.cols, 64);
  EXPECT_EQ(pixels.rows, 48);
}

}  // namespace
}  // namespace lidarseg::vision
