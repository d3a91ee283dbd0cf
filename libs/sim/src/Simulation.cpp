#include "lidarseg/sim/Simulation.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/Angles.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace lidarseg::sim {

namespace {
void requirePositive(const char* key, double v) {
  if (!(std::isfinite(v) && v > 0.0)) {
    throw std::invalid_argument(std::string(key) + " must be finite and > 0 (got " + numberText(v) + ")");
  }
}
void requireNonNegative(const char* key, double v) {
  if (!(std::isfinite(v) && v >= 0.0)) {
    throw std::invalid_argument(std::string(key) + " must be finite and >= 0 (got " + numberText(v) + ")");
  }
}
void requireFinite(const char* key, double v) {
  if (!std::isfinite(v)) throw std::invalid_argument(std::string(key) + " must be finite (got " + numberText(v) + ")");
}
// A value whose magnitude no robot, camera or noise model has: it reached the outputs as
// 300-digit numbers (issue 16).
void requireAtMost(const char* key, double v, double bound, const char* unit) {
  if (!(std::abs(v) <= bound)) {
    throw std::invalid_argument(std::string(key) + " must be within +-" + numberText(bound) + " " + unit + " (got " +
                                numberText(v) + ")");
  }
}
}  // namespace

void SimulationParams::validate() const {
  if (!sensor.layout || sensor.layout->size() < 2) throw std::invalid_argument("sensor needs at least 2 beams");
  requirePositive("max_range_m", sensor.max_range_m);
  // A sensor's scans need some range to measure: the scan's own check would fail later,
  // naming no key.
  if (!(sensor.max_range_m > sensor.min_range_m)) {
    throw std::invalid_argument("max_range_m must be greater than the sensor's minimum range, " +
                                numberText(sensor.min_range_m) + " m (got " + numberText(sensor.max_range_m) + ")");
  }
  requireNonNegative("range_sigma_m", sensor.range_sigma_m);
  requireNonNegative("far_range_sigma_m", sensor.far_range_sigma_m);
  // A scanner turns between 0.1 and 1000 times a second; beyond, the stamps reach 300 digits
  // or the beams share one instant (issue 16).
  if (!(std::isfinite(sensor.frequency_hz) && sensor.frequency_hz >= 0.1 && sensor.frequency_hz <= 1000.0)) {
    throw std::invalid_argument("frequency_hz must be in [0.1, 1000] Hz (got " + numberText(sensor.frequency_hz) + ")");
  }
  requireNonNegative("lidar_z_m", lidar_z_m);
  requireNonNegative("field_of_view_rad", field_of_view_rad);
  if (field_of_view_rad > 2.0 * kPi + 1e-9) {
    throw std::invalid_argument("field_of_view_rad must be <= 2 pi (got " + numberText(field_of_view_rad) + ")");
  }
  if (num_beams == 1 || num_beams > kMaxBeams) {
    throw std::invalid_argument("num_beams must be 0 (profile) or in [2, 100000] (got " + std::to_string(num_beams) +
                                ")");
  }
  // A stamp must still tell two scans 1 ms apart: |t| <= 1e10 s (the year 2286) keeps a double's spacing
  // near t below 2e-6 s, and the log readers skip stamps beyond it; the start leaves 1e9 s of run
  // below that (issue 16).
  if (!(std::isfinite(start_time_s) && std::abs(start_time_s) <= kMaxAbsStartTimeS)) {
    std::ostringstream os;
    os << "start_time_s must be finite and in [-9e9, 9e9] s (got " << start_time_s << ")";
    throw std::invalid_argument(os.str());
  }
  if (static_cast<std::size_t>(scan_stamp) > 2) {
    throw std::invalid_argument("scan_stamp must be 0 (first beam), 1 (middle) or 2 (last beam)");
  }
  if (camera.width < 16 || camera.width > 8192) {
    throw std::invalid_argument("camera_width must be in [16, 8192] (got " + std::to_string(camera.width) + ")");
  }
  if (camera.height < 16 || camera.height > 8192) {
    throw std::invalid_argument("camera_height must be in [16, 8192] (got " + std::to_string(camera.height) + ")");
  }
  requireFinite("camera_cx", camera.cx);
  requireFinite("camera_cy", camera.cy);
  requireFinite("camera_x_m", camera.x_m);
  requireFinite("camera_y_m", camera.y_m);
  requireFinite("camera_yaw_rad", camera.yaw_rad);
  requirePositive("camera_fx", camera.fx);
  requirePositive("camera_fy", camera.fy);
  requirePositive("camera_z_m", camera.z_m);
  requirePositive("wall_height_m", heights.wall_m);
  requirePositive("door_height_m", heights.door_m);
  requireNonNegative("odom_translation_per_m", odometry.translation_per_m);
  requireNonNegative("odom_rotation_per_rad", odometry.rotation_per_rad);
  requireNonNegative("odom_rotation_per_m", odometry.rotation_per_m);
  requireAtMost("range_sigma_m", sensor.range_sigma_m, 100.0, "m");
  requireAtMost("far_range_sigma_m", sensor.far_range_sigma_m, 100.0, "m");
  requireAtMost("lidar_z_m", lidar_z_m, 1e3, "m");
  requireAtMost("camera_cx", camera.cx, 1e5, "px");
  requireAtMost("camera_cy", camera.cy, 1e5, "px");
  requireAtMost("camera_fx", camera.fx, 1e6, "px");
  requireAtMost("camera_fy", camera.fy, 1e6, "px");
  requireAtMost("camera_x_m", camera.x_m, 1e3, "m");
  requireAtMost("camera_y_m", camera.y_m, 1e3, "m");
  requireAtMost("camera_z_m", camera.z_m, 1e3, "m");
  requireAtMost("camera_yaw_rad", camera.yaw_rad, 2.0 * kPi, "rad");
  requireAtMost("wall_height_m", heights.wall_m, 1e3, "m");
  requireAtMost("door_height_m", heights.door_m, 1e3, "m");
  requireAtMost("odom_translation_per_m", odometry.translation_per_m, 10.0, "(m per m)");
  requireAtMost("odom_rotation_per_rad", odometry.rotation_per_rad, 10.0, "(rad per rad)");
  requireAtMost("odom_rotation_per_m", odometry.rotation_per_m, 10.0, "(rad per m)");
}


SensorModel sensorProfile(const std::string& name) {
  if (name == "lms100") return SensorModel::lms100();
  if (name == "utm30lx") return SensorModel::utm30lx();
  if (name == "sick180") return SensorModel::sick180();
  if (name == "rplidar360") return SensorModel::rplidar360();
  throw std::invalid_argument("unknown sensor profile '" + name + "' (lms100, utm30lx, sick180, rplidar360)");
}

namespace {
SimulationParams withSensorOverrides(SimulationParams p) {
  p.validate();
  if (p.num_beams > 0 || p.field_of_view_rad > 0.0) {
    const std::size_t n = p.num_beams > 0 ? p.num_beams : p.sensor.layout->size();
    const double fov = p.field_of_view_rad > 0.0
                           ? p.field_of_view_rad
                           : std::abs(p.sensor.layout->angles().back() - p.sensor.layout->angles().front());
    p.sensor.layout = std::make_shared<BeamLayout>(BeamLayout::centred(n, fov));
  }
  return p;
}
}  // namespace

Simulation::Simulation(const World& world, const Trajectory& trajectory, const SimulationParams& params)
    : world_(&world),
      trajectory_(&trajectory),
      params_(withSensorOverrides(params)),
      lidar_(world, params_.sensor, params.seed * 4 + 0),
      odometry_(params.odometry, params.seed * 4 + 1),
      camera_(world, params.camera, params.heights),
      oracle_(world) {
  const double scans = std::floor(trajectory.duration() * params.sensor.frequency_hz) + 1.0;
  if (!(scans <= static_cast<double>(kMaxScans))) {
    throw std::invalid_argument("the trajectory lasts " + numberText(trajectory.duration()) + " s: " +
                                std::to_string(scans) + " scans at " + numberText(params.sensor.frequency_hz) +
                                " Hz, more than the " + std::to_string(kMaxScans) + " a simulation may write");
  }
  num_scans_ = static_cast<std::size_t>(scans);
}

SimulatedFrame Simulation::next() {
  if (next_ >= num_scans_) throw std::out_of_range("Simulation::next: past the last scan");
  SimulatedFrame f;
  f.index = next_++;
  const double t = static_cast<double>(f.index) / params_.sensor.frequency_hz;  // first beam
  const double sweep = params_.rolling_shutter ? lidar_.sweepDuration() : 0.0;
  const double shift = params_.scan_stamp == ScanStamp::kMiddle ? 0.5 * sweep
                       : params_.scan_stamp == ScanStamp::kLast ? sweep
                                                                : 0.0;
  f.stamp_s = params_.start_time_s + t + shift;
  f.T_world_robot = trajectory_->poseAt(t + shift);
  const Pose2D first = trajectory_->poseAt(t);
  const Pose2D last = params_.rolling_shutter ? trajectory_->poseAt(t + sweep) : first;
  f.scan = lidar_.scan(first, last);
  f.scan.stamp_s = f.stamp_s;
  if (!params_.rolling_shutter) {
    f.scan.time_offsets_s.assign(f.scan.size(), 0.0);
  } else {
    for (double& o : f.scan.time_offsets_s) o -= shift;
  }
  f.odometry = odometry_.update(f.T_world_robot);
  f.features = oracle_.visible(f.T_world_robot, *params_.sensor.layout, params_.sensor.max_range_m);
  if (params_.camera_every_scans > 0 && f.index % params_.camera_every_scans == 0) {
    f.has_image = true;
    f.image = camera_.render(f.T_world_robot);
    f.door_boxes = camera_.visibleDoors(f.T_world_robot);
  }
  return f;
}

}  // namespace lidarseg::sim
