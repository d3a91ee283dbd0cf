#pragma once
/// @file CameraModel.h
/// A calibrated camera rigidly mounted beside the lidar (paper §III.B, eq. 1: p = K T P).

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace lidarseg::vision {

/// Intrinsics, distortion, image size and pose of a camera relative to the lidar.
///
/// Frames: the lidar frame has x forward, y left, z up, its origin at the lidar's optical
/// centre; the camera frame is OpenCV's (x right, y down, z along the optical axis).
/// The camera's pose in the lidar frame is given as a position (m) and yaw, pitch, roll
/// (rad) of its optical axis: yaw about the lidar's z (0: looking along the lidar's x),
/// pitch down positive, roll about the optical axis.
struct CameraParams {
  int width = 640, height = 480;  ///< pixels
  double fx = 554.256, fy = 554.256, cx = 319.5, cy = 239.5;  ///< K (pixels)
  /// OpenCV's distortion coefficients (k1, k2, p1, p2, k3); zeros: none.
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  double x_m = 0.1, y_m = 0.0, z_m = 0.3;  ///< camera position in the lidar frame
  double yaw_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;

  /// @throws std::invalid_argument naming the key (width, fx, ...).
  void validate() const;
};

/// The camera model used to turn lidar features into image regions.
class CameraModel {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit CameraModel(const CameraParams& params = {});
  /// A camera whose pose comes as a matrix (e.g. from a log's calibration): the intrinsics,
  /// distortion and image size of `intrinsics` (its pose fields are ignored) and
  /// T_camera_lidar, lidar-frame points to camera-frame points.
  /// @throws std::invalid_argument for invalid intrinsics or a matrix that is not a rigid
  /// transformation.
  CameraModel(const CameraParams& intrinsics, const Eigen::Matrix4d& T_camera_lidar);

  const CameraParams& params() const { return params_; }
  /// T_camera_lidar (4 x 4): lidar-frame points to camera-frame points.
  const Eigen::Matrix4d& T_camera_lidar() const { return T_camera_lidar_; }
  /// Lidar-frame point to the camera frame (m).
  Eigen::Vector3d toCamera(const Eigen::Vector3d& P_lidar) const;

  /// Projects camera-frame points (all with z > 0) to pixels with cv::projectPoints (K and
  /// the distortion).
  std::vector<cv::Point2d> projectCameraPoints(const std::vector<cv::Point3d>& P_camera) const;
  /// Paper eq. 1 for one lidar-frame point: false when it lies behind the camera.
  bool project(const Eigen::Vector3d& P_lidar, Eigen::Vector2d& pixel) const;

 private:
  CameraParams params_;
  Eigen::Matrix4d T_camera_lidar_;
  cv::Matx33d K_;
  cv::Mat distortion_;

  void setIntrinsics();
};

}  // namespace lidarseg::vision
