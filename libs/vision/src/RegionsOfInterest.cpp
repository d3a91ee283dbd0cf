#include "lidarseg/vision/RegionsOfInterest.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lidarseg::vision {

namespace {
constexpr double kNear = 0.05;  // m: the near clipping plane in front of the camera
}  // namespace

void RoiParams::validate() const {
  auto positive = [](const char* key, double v) {
    if (!(std::isfinite(v) && v > 0)) {
      throw std::invalid_argument(std::string(key) + " must be finite and > 0 (got " + numberText(v) + ")");
    }
  };
  if (!(std::isfinite(lidar_height_m) && lidar_height_m >= 0)) {
    throw std::invalid_argument("lidar_height_m must be finite and >= 0 (got " + numberText(lidar_height_m) + ")");
  }
  positive("door_height_m", door_height_m);
  positive("corner_strip_m", corner_strip_m);
  positive("corner_height_m", corner_height_m);
  if (min_size_px < 1) throw std::invalid_argument("min_size_px must be >= 1 (got " + std::to_string(min_size_px) + ")");
}

RoiProjector::RoiProjector(CameraModel camera, const RoiParams& params) : camera_(std::move(camera)), params_(params) {
  params_.validate();
}

bool RoiProjector::boxOfQuad(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z0, double z1, cv::Rect& box,
                             bool& clipped) const {
  // The quad's four corners in the camera frame; clip each vertical edge pair against the
  // near plane along the bottom and top edges.
  std::vector<cv::Point3d> pts;
  for (double z : {z0, z1}) {
    Eigen::Vector3d p = camera_.toCamera({a.x(), a.y(), z});
    Eigen::Vector3d q = camera_.toCamera({b.x(), b.y(), z});
    const bool p_in = p.z() >= kNear, q_in = q.z() >= kNear;
    if (!p_in && !q_in) continue;
    if (!p_in || !q_in) {
      clipped = true;
      const double t = (kNear - p.z()) / (q.z() - p.z());
      const Eigen::Vector3d cut = p + t * (q - p);
      (p_in ? q : p) = cut;
    }
    pts.emplace_back(p.x(), p.y(), p.z());
    pts.emplace_back(q.x(), q.y(), q.z());
  }
  if (pts.empty()) return false;
  const auto px = camera_.projectCameraPoints(pts);
  double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
  for (const auto& p : px) {
    u0 = std::min(u0, p.x), v0 = std::min(v0, p.y), u1 = std::max(u1, p.x), v1 = std::max(v1, p.y);
  }
  const int w = camera_.params().width, h = camera_.params().height;
  const double cu0 = std::max(u0, 0.0), cv0 = std::max(v0, 0.0);
  const double cu1 = std::min(u1, w - 1.0), cv1 = std::min(v1, h - 1.0);
  if (cu0 != u0 || cv0 != v0 || cu1 != u1 || cv1 != v1) clipped = true;
  if (cu1 < cu0 || cv1 < cv0) return false;
  const int x0 = static_cast<int>(std::floor(cu0)), y0 = static_cast<int>(std::floor(cv0));
  box = cv::Rect(x0, y0, static_cast<int>(std::ceil(cu1)) - x0 + 1, static_cast<int>(std::ceil(cv1)) - y0 + 1);
  return box.width >= params_.min_size_px && box.height >= params_.min_size_px;
}

std::vector<Roi> RoiProjector::project(const std::vector<Feature>& features) const {
  std::vector<Roi> out;
  const double floor_z = -params_.lidar_height_m;
  const Eigen::Vector3d cam = camera_.T_camera_lidar().topLeftCorner<3, 3>().transpose() *
                              -camera_.T_camera_lidar().topRightCorner<3, 1>();  // camera centre, lidar frame
  for (std::size_t i = 0; i < features.size(); ++i) {
    const Feature& f = features[i];
    Eigen::Vector2d a, b;
    double top;
    if (isDoor(f.type)) {
      a = f.jamb_a;
      b = f.jamb_b;
      top = floor_z + params_.door_height_m;
    } else {
      Eigen::Vector2d sight = f.position - cam.head<2>();
      if (sight.norm() < 1e-9) continue;
      sight.normalize();
      const Eigen::Vector2d across(-sight.y(), sight.x());
      a = f.position - 0.5 * params_.corner_strip_m * across;
      b = f.position + 0.5 * params_.corner_strip_m * across;
      top = floor_z + params_.corner_height_m;
    }
    Roi roi;
    roi.feature = i;
    roi.type = f.type;
    if (boxOfQuad(a, b, floor_z, top, roi.box, roi.clipped)) out.push_back(roi);
  }
  return out;
}

double intersectionOverUnion(const cv::Rect& a, const cv::Rect& b) {
  const double inter = (a & b).area();
  const double uni = static_cast<double>(a.area()) + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

cv::Rect grow(const cv::Rect& box, double margin, const cv::Size& image) {
  // In floating point, clipped to the image before any conversion: a large margin or box
  // must not overflow an int (issue 16).
  const double dx = std::round(margin * box.width), dy = std::round(margin * box.height);
  const double x0 = std::clamp(box.x - dx, 0.0, static_cast<double>(image.width));
  const double y0 = std::clamp(box.y - dy, 0.0, static_cast<double>(image.height));
  const double x1 = std::clamp(box.x + box.width + dx, 0.0, static_cast<double>(image.width));
  const double y1 = std::clamp(box.y + box.height + dy, 0.0, static_cast<double>(image.height));
  if (!(x1 > x0 && y1 > y0)) return cv::Rect();
  return cv::Rect(static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(x1 - x0), static_cast<int>(y1 - y0));
}

double coveredFraction(const std::vector<cv::Rect>& boxes, const cv::Size& image) {
  if (image.area() == 0) return 0.0;
  cv::Mat mask(image, CV_8U, cv::Scalar(0));
  for (const cv::Rect& r : boxes) mask(r & cv::Rect(cv::Point(0, 0), image)).setTo(1);
  return static_cast<double>(cv::countNonZero(mask)) / image.area();
}

}  // namespace lidarseg::vision
