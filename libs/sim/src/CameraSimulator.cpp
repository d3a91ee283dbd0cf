#include "lidarseg/sim/CameraSimulator.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "lidarseg/sim/OdometrySimulator.h"

namespace lidarseg::sim {

namespace {
// Points closer than this to the camera plane are not projected (m).
constexpr double kNear = 0.05;
// Colours (RGB).
constexpr std::uint8_t kWallRgb[3] = {200, 200, 190};
constexpr std::uint8_t kDoorRgb[3] = {150, 90, 40};
constexpr std::uint8_t kClutterRgb[3] = {70, 110, 160};
constexpr std::uint8_t kFloorRgb[3] = {90, 85, 80};
constexpr std::uint8_t kCeilingRgb[3] = {235, 235, 235};

void put(std::uint8_t* px, const std::uint8_t rgb[3], double shade) {
  for (int k = 0; k < 3; ++k) px[k] = static_cast<std::uint8_t>(std::clamp(rgb[k] * shade, 0.0, 255.0));
}
}  // namespace

Eigen::Matrix4d PinholeCamera::T_camera_robot() const {
  // Robot axes (forward, left, up) to camera axes (right, down, forward), after undoing the
  // camera's position and heading.
  Eigen::Matrix3d axes;
  axes << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  Eigen::Matrix3d yaw;
  yaw << std::cos(yaw_rad), std::sin(yaw_rad), 0, -std::sin(yaw_rad), std::cos(yaw_rad), 0, 0, 0, 1;
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = axes * yaw;
  T.topRightCorner<3, 1>() = -axes * yaw * Eigen::Vector3d(x_m, y_m, z_m);
  return T;
}

CameraSimulator::CameraSimulator(const World& world, PinholeCamera camera, SceneHeights heights)
    : world_(&world), camera_(camera), heights_(heights), caster_(world) {}

bool CameraSimulator::project(const Eigen::Vector3d& P, Eigen::Vector2d& pixel) const {
  const Eigen::Vector4d q = camera_.T_camera_robot() * P.homogeneous();
  if (q.z() < kNear) return false;
  pixel = {camera_.fx * q.x() / q.z() + camera_.cx, camera_.fy * q.y() / q.z() + camera_.cy};
  return true;
}

RgbImage CameraSimulator::render(const Pose2D& T_world_robot) const {
  const PinholeCamera& c = camera_;
  RgbImage img{c.width, c.height, std::vector<std::uint8_t>(static_cast<std::size_t>(c.width) * c.height * 3)};
  const Pose2D cam = compose(T_world_robot, {c.x_m, c.y_m, c.yaw_rad});
  const Eigen::Vector2d origin(cam.x, cam.y);
  for (int u = 0; u < c.width; ++u) {
    const double xc = (u - c.cx) / c.fx;      // right per unit forward
    const double alpha = std::atan2(-xc, 1.0);  // left of the optical axis
    const double a = cam.yaw + alpha;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const RayHit hit = caster_.cast(origin, dir, 100.0);
    double forward = hit.range * std::cos(alpha);  // depth along the optical axis
    SurfaceKind kind = SurfaceKind::kWall;
    double shade = 1.0;
    if (hit.hit()) {
      const Wall& w = caster_.walls()[hit.wall];
      kind = w.kind;
      const Eigen::Vector2d e = (w.b - w.a).normalized();
      const double incidence = std::abs(dir.x() * e.y() - dir.y() * e.x());  // |sin| to the wall
      shade = (0.55 + 0.45 * incidence) / (1.0 + 0.04 * hit.range);
    } else {
      forward = 1e9;
    }
    for (int v = 0; v < c.height; ++v) {
      const double yc = (v - c.cy) / c.fy;  // down per unit forward
      const double z = c.z_m - yc * forward;  // height where this pixel's ray meets the wall
      std::uint8_t* px = &img.rgb[(static_cast<std::size_t>(v) * c.width + u) * 3];
      if (hit.hit() && z >= 0.0 && z <= heights_.wall_m) {
        if (kind == SurfaceKind::kDoor && z <= heights_.door_m) {
          put(px, kDoorRgb, shade);
        } else if (kind == SurfaceKind::kClutter) {
          put(px, kClutterRgb, shade);
        } else {
          put(px, kWallRgb, shade);
        }
      } else if (yc > 0.0) {
        // Floor: darker far away (towards the horizon).
        const double dist = c.z_m / yc;
        put(px, kFloorRgb, 1.0 / (1.0 + 0.03 * dist));
      } else {
        put(px, kCeilingRgb, 1.0);
      }
    }
  }
  return img;
}

std::vector<DoorBox> CameraSimulator::visibleDoors(const Pose2D& T_world_robot) const {
  std::vector<DoorBox> boxes;
  const PinholeCamera& c = camera_;
  const Pose2D cam = compose(T_world_robot, {c.x_m, c.y_m, c.yaw_rad});
  const Eigen::Vector2d origin(cam.x, cam.y);
  const Eigen::Vector2d axis(std::cos(cam.yaw), std::sin(cam.yaw));
  for (std::size_t i = 0; i < world_->doors().size(); ++i) {
    const Door& door = world_->doors()[i];
    // Visible: some point of the doorway lies inside the image's horizontal field of view
    // and is reached by a ray from the camera.
    bool visible = false;
    for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      const Eigen::Vector2d p = door.jamb_a + f * (door.jamb_b - door.jamb_a);
      const Eigen::Vector2d d = p - origin;
      const double dist = d.norm();
      const double forward = d.dot(axis);
      if (dist < 1e-6 || forward < kNear) continue;
      const double left = axis.x() * d.y() - axis.y() * d.x();
      const double u = c.cx - c.fx * left / forward;
      if (u < 0.0 || u > c.width - 1.0) continue;
      if (caster_.cast(origin, d / dist, dist + 1.0).range >= dist - 0.05) {
        visible = true;
        break;
      }
    }
    if (!visible) continue;
    // Clip the doorway to the part in front of the camera, then project its four corners.
    Eigen::Vector2d a = door.jamb_a, b = door.jamb_b;
    const double fa = (a - origin).dot(axis) - kNear, fb = (b - origin).dot(axis) - kNear;
    if (fa < 0 && fb < 0) continue;
    if (fa < 0) a = a + (b - a) * (fa / (fa - fb));
    if (fb < 0) b = b + (a - b) * (fb / (fb - fa));
    double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
    bool any = false;
    for (const Eigen::Vector2d& w : {a, b}) {
      const Pose2D local = relative({w.x(), w.y(), 0.0}, T_world_robot);
      for (double z : {0.0, heights_.door_m}) {
        Eigen::Vector2d px;
        if (!project({local.x, local.y, z}, px)) continue;
        any = true;
        u0 = std::min(u0, px.x());
        v0 = std::min(v0, px.y());
        u1 = std::max(u1, px.x());
        v1 = std::max(v1, px.y());
      }
    }
    if (!any) continue;
    DoorBox box{i, static_cast<int>(std::floor(std::max(u0, 0.0))),
                static_cast<int>(std::floor(std::max(v0, 0.0))),
                static_cast<int>(std::ceil(std::min(u1, c.width - 1.0))),
                static_cast<int>(std::ceil(std::min(v1, c.height - 1.0)))};
    if (box.u_min > box.u_max || box.v_min > box.v_max || u1 < 0 || v1 < 0 || u0 > c.width - 1 ||
        v0 > c.height - 1) {
      continue;
    }
    boxes.push_back(box);
  }
  return boxes;
}

}  // namespace lidarseg::sim
