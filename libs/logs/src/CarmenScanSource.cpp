#include "lidarseg/logs/CarmenScanSource.h"

#include <stdexcept>

#include "lidarseg/logs/CarmenScan.h"

namespace lidarseg::logs {

namespace {
CarmenReaderOptions optionsFor(const std::string& laser_type) {
  CarmenReaderOptions options;
  options.laser_type = laser_type;
  return options;
}
}  // namespace

CarmenScanSource::CarmenScanSource(const std::string& path, const std::string& laser_type)
    : ScanSource(path), reader_(path, optionsFor(laser_type)) {}

std::vector<std::string> CarmenScanSource::unknownTypes() const {
  std::vector<std::string> out;
  for (const auto& [type, n] : reader_.unknownTypes()) {
    out.push_back(path() + ": " + std::to_string(n) + " line(s) of unknown type '" + type + "' skipped");
  }
  return out;
}

std::string CarmenScanSource::unreadScans() const {
  std::string lines;
  for (const auto& [type, n] : reader_.unreadLaserLines()) {
    lines += (lines.empty() ? "" : ", ") + std::to_string(n) + " " + type + " line(s)";
  }
  if (lines.empty()) return {};
  return "it holds " + lines + ", a laser type not read (FLASER, RLASER and ROBOTLASER1 are)";
}

std::optional<ScanRecord> CarmenScanSource::read() {
  while (true) {
    const std::size_t malformed_before = reader_.malformedLines();
    auto laser = reader_.next();
    // Lines the CARMEN reader skipped are this source's issues too.
    for (std::size_t k = malformed_before; k < reader_.malformedLines(); ++k) {
      note(k < reader_.issues().size() ? reader_.issues()[k] : path() + ": malformed line");
    }
    if (!laser) return std::nullopt;
    if (laser->ranges_m.size() < 2 || !(laser->angular_resolution_rad != 0.0) || !(laser->max_range_m > 0.0)) {
      note(path() + ":" + std::to_string(laser->line) + ": " + laser->type + " with " +
           std::to_string(laser->ranges_m.size()) + " beam(s) (need 2 or more) skipped");
      continue;
    }
    ScanRecord r;
    r.where = path() + ":" + std::to_string(laser->line);
    r.stamp_s = laser->stamp_s;
    r.sensor = laser->type;
    // A line the core cannot represent (an aperture overflowing to infinity) is skipped with
    // its place.
    try {
      r.scan = carmenScan(*laser, layouts_);
    } catch (const std::invalid_argument& e) {
      note(r.where + ": " + e.what() + "; line skipped");
      continue;
    }
    r.sensor_on_robot = carmenSensorOnRobot(*laser);
    // Raw wheel odometry: the last ODOM line when the log has them (corrected logs rewrite
    // the laser line's odometry fields), else the laser line's own fields.
    r.odometry = reader_.lastOdometry() ? *reader_.lastOdometry() : laser->robot_pose;
    r.log_pose = compose(laser->laser_pose, inverse(laser->laser_on_robot));
    return r;
  }
}

}  // namespace lidarseg::logs
