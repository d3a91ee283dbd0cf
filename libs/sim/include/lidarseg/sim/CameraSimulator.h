#pragma once
/// @file CameraSimulator.h
/// A pinhole camera that renders a World and knows where its doors appear.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// A level pinhole camera mounted on the robot. Camera frame as in OpenCV: x right,
/// y down, z forward (optical axis). Robot/lidar frame: x forward, y left, z up from the floor.
struct PinholeCamera {
  int width = 640;
  int height = 480;
  /// Intrinsics K (pixels): 60 degrees of horizontal field of view at 640 x 480.
  double fx = 554.256, fy = 554.256, cx = 319.5, cy = 239.5;
  /// Camera position in the robot frame (m) and heading of its optical axis (rad).
  double x_m = 0.1, y_m = 0.0, z_m = 0.6, yaw_rad = 0.0;

  /// The 4x4 transform T_camera_robot (robot frame -> camera frame).
  Eigen::Matrix4d T_camera_robot() const;
};

/// Heights of what the camera sees (m).
struct SceneHeights {
  double wall_m = 2.5;
  double door_m = 2.0;
};

/// An 8-bit RGB image, rows top to bottom.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3
};

/// Where a door appears in an image (pixels, inclusive bounds).
struct DoorBox {
  std::size_t door = 0;  ///< index in World::doors()
  int u_min = 0, v_min = 0, u_max = 0, v_max = 0;
};

/// Renders a World (walls shaded, doors in their own colour, floor and ceiling) by casting
/// one ray per pixel column, and gives the ground-truth box of each visible door.
class CameraSimulator {
 public:
  CameraSimulator(const World& world, PinholeCamera camera, SceneHeights heights = {});

  RgbImage render(const Pose2D& T_world_robot) const;

  /// Boxes of the doors at least partly visible from the camera (a point of the doorway, at
  /// 10-90 % of its width, inside the horizontal field of view and not hidden by a wall):
  /// the doorway from the floor to the door height, projected (paper eq. 1) and clipped.
  std::vector<DoorBox> visibleDoors(const Pose2D& T_world_robot) const;

  /// Projects a point of the robot frame to pixels (paper eq. 1, p = K T P); false when the
  /// point is behind the camera.
  bool project(const Eigen::Vector3d& P_robot, Eigen::Vector2d& pixel) const;

  const PinholeCamera& camera() const { return camera_; }

 private:
  const World* world_;
  PinholeCamera camera_;
  SceneHeights heights_;
  RayCaster caster_;
};

}  // namespace lidarseg::sim
