// The camera's projection (paper eq. 1) against its own rendering: every pixel painted as
// a door leaf must fall inside the projected box of a visible door.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "lidarseg/sim/CameraSimulator.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

namespace lidarseg::sim {
namespace {

bool isDoorPixel(const RgbImage& img, int u, int v) {
  const std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(v) * img.width + u) * 3];
  // Door leaves are brown (red > green > blue, clearly), walls grey, clutter blue.
  return p[0] > p[1] + 25 && p[1] > p[2] + 25;
}

TEST(CameraSimulator, ProjectsPointsWithK) {
  const World w;
  const CameraSimulator cam(w, PinholeCamera{});
  Eigen::Vector2d px;
  // A point straight ahead at the camera's height lands on the principal point.
  ASSERT_TRUE(cam.project({5.1, 0.0, 0.6}, px));
  EXPECT_NEAR(px.x(), 319.5, 1e-9);
  EXPECT_NEAR(px.y(), 239.5, 1e-9);
  // 1 m to the left (robot +y) at 5 m depth: u = cx - fx / 5.
  ASSERT_TRUE(cam.project({5.1, 1.0, 0.6}, px));
  EXPECT_NEAR(px.x(), 319.5 - 554.256 / 5.0, 1e-9);
  // Higher is up in the image.
  ASSERT_TRUE(cam.project({5.1, 0.0, 1.6}, px));
  EXPECT_NEAR(px.y(), 239.5 - 554.256 / 5.0, 1e-9);
  EXPECT_FALSE(cam.project({-1.0, 0.0, 0.6}, px));
}

TEST(CameraSimulator, DoorPixelsLieInsideTheGroundTruthBoxes) {
  const std::string dir = std::string(LIDARSEG_CONFIG_DIR) + "/worlds/";
  const World world = loadWorldFile(dir + "hospital.world");
  const Trajectory traj = loadTrajectoryFile(dir + "hospital.traj");
  const CameraSimulator cam(world, PinholeCamera{});
  std::size_t door_pixels = 0, boxes_total = 0;
  for (double t = 0.0; t < traj.duration(); t += 4.0) {
    const Pose2D pose = traj.poseAt(t);
    const RgbImage img = cam.render(pose);
    const auto boxes = cam.visibleDoors(pose);
    boxes_total += boxes.size();
    for (const DoorBox& b : boxes) {
      EXPECT_GE(b.u_min, 0);
      EXPECT_GE(b.v_min, 0);
      EXPECT_LT(b.u_max, img.width);
      EXPECT_LT(b.v_max, img.height);
      EXPECT_LE(b.u_min, b.u_max);
    }
    for (int v = 0; v < img.height; ++v) {
      for (int u = 0; u < img.width; ++u) {
        if (!isDoorPixel(img, u, v)) continue;
        ++door_pixels;
        const bool inside = std::any_of(boxes.begin(), boxes.end(), [&](const DoorBox& b) {
          return u >= b.u_min - 2 && u <= b.u_max + 2 && v >= b.v_min - 2 && v <= b.v_max + 2;
        });
        ASSERT_TRUE(inside) << "door pixel (" << u << ", " << v << ") outside every box at t = " << t;
      }
    }
  }
  EXPECT_GT(door_pixels, 1000u);
  EXPECT_GT(boxes_total, 20u);
}

}  // namespace
}  // namespace lidarseg::sim
