#include "lidarseg/vision/CameraModel.h"
#include "lidarseg/core/NumberText.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

namespace lidarseg::vision {

namespace {
[[noreturn]] void fail(const std::string& key, const std::string& need, double value) {
  throw std::invalid_argument(key + " must be " + need + " (got " + numberText(value) + ")");
}
constexpr double kNear = 1e-3;  // m: points closer to the camera plane are "behind"
}  // namespace

void CameraParams::validate() const {
  if (width <= 0) fail("width", "> 0", width);
  if (height <= 0) fail("height", "> 0", height);
  for (const auto& [key, v] : {std::pair<const char*, double>{"fx", fx}, {"fy", fy}}) {
    if (!(std::isfinite(v) && v > 0)) fail(key, "finite and > 0", v);
  }
  for (const auto& [key, v] : {std::pair<const char*, double>{"cx", cx}, {"cy", cy}, {"k1", k1}, {"k2", k2},
                               {"p1", p1}, {"p2", p2}, {"k3", k3}, {"x_m", x_m}, {"y_m", y_m}, {"z_m", z_m},
                               {"yaw_rad", yaw_rad}, {"pitch_rad", pitch_rad}, {"roll_rad", roll_rad}}) {
    if (!std::isfinite(v)) fail(key, "finite", v);
  }
}

CameraModel::CameraModel(const CameraParams& params) : params_(params) {
  params_.validate();
  const double cy = std::cos(params_.yaw_rad), sy = std::sin(params_.yaw_rad);
  const double cp = std::cos(params_.pitch_rad), sp = std::sin(params_.pitch_rad);
  const double cr = std::cos(params_.roll_rad), sr = std::sin(params_.roll_rad);
  // Axes of a level camera looking along the lidar's x: camera x = -lidar y, camera y =
  // -lidar z, camera z = lidar x. Then the camera turns: yaw about the lidar's z, pitch
  // down about its own x, roll about its optical axis.
  Eigen::Matrix3d Rz;  // lidar <- yawed lidar
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  Eigen::Matrix3d axes;  // yawed lidar <- level camera
  axes << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Matrix3d Rx;  // level camera <- pitched camera (pitch down: +y of the image goes forward)
  Rx << 1, 0, 0, 0, cp, sp, 0, -sp, cp;
  Eigen::Matrix3d Rr;  // about the optical axis
  Rr << cr, -sr, 0, sr, cr, 0, 0, 0, 1;
  const Eigen::Matrix3d R_lidar_camera = Rz * axes * Rx * Rr;
  T_camera_lidar_.setIdentity();
  T_camera_lidar_.topLeftCorner<3, 3>() = R_lidar_camera.transpose();
  T_camera_lidar_.topRightCorner<3, 1>() =
      -R_lidar_camera.transpose() * Eigen::Vector3d(params_.x_m, params_.y_m, params_.z_m);
  setIntrinsics();
}

CameraModel::CameraModel(const CameraParams& intrinsics, const Eigen::Matrix4d& T_camera_lidar)
    : params_(intrinsics), T_camera_lidar_(T_camera_lidar) {
  params_.validate();
  const Eigen::Matrix3d R = T_camera_lidar_.topLeftCorner<3, 3>();
  const bool finite = T_camera_lidar_.allFinite();
  if (!finite || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || std::abs(R.determinant() - 1) > 1e-6 ||
      (T_camera_lidar_.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-12) {
    throw std::invalid_argument("T_camera_lidar must be a rigid transformation (rotation and translation)");
  }
  setIntrinsics();
}

void CameraModel::setIntrinsics() {
  K_ = cv::Matx33d(params_.fx, 0, params_.cx, 0, params_.fy, params_.cy, 0, 0, 1);
  distortion_ = (cv::Mat_<double>(1, 5) << params_.k1, params_.k2, params_.p1, params_.p2, params_.k3);
}

Eigen::Vector3d CameraModel::toCamera(const Eigen::Vector3d& P) const {
  return T_camera_lidar_.topLeftCorner<3, 3>() * P + T_camera_lidar_.topRightCorner<3, 1>();
}

std::vector<cv::Point2d> CameraModel::projectCameraPoints(const std::vector<cv::Point3d>& P) const {
  std::vector<cv::Point2d> out;
  if (P.empty()) return out;
  cv::projectPoints(P, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K_, distortion_, out);
  return out;
}

bool CameraModel::project(const Eigen::Vector3d& P_lidar, Eigen::Vector2d& pixel) const {
  const Eigen::Vector3d q = toCamera(P_lidar);
  if (q.z() < kNear) return false;
  const auto px = projectCameraPoints({cv::Point3d(q.x(), q.y(), q.z())});
  pixel = {px[0].x, px[0].y};
  return true;
}

}  // namespace lidarseg::vision
