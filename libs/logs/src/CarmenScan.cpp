#include "lidarseg/logs/CarmenScan.h"
#include "lidarseg/core/NumberText.h"

#include <cmath>
#include <string>

namespace lidarseg::logs {

Scan carmenScan(const CarmenLaser& laser, CentredLayoutCache& layouts) {
  const std::size_t n = laser.ranges_m.size();
  const double res = laser.angular_resolution_rad;
  if (n < 2 || !(res != 0.0)) {
    throw std::invalid_argument(laser.type + " with " + std::to_string(n) + " beam(s) and a resolution of " +
                                numberText(res) + " rad: at least 2 beams and a non-zero resolution are needed");
  }
  const float aperture = static_cast<float>(std::abs(res) * static_cast<double>(n - 1));
  if (!std::isfinite(aperture) || aperture <= 0.0f) {
    throw std::invalid_argument(laser.type + " has an invalid aperture (" + numberText(static_cast<double>(aperture)) + " rad)");
  }
  const double max_range = static_cast<double>(static_cast<float>(laser.max_range_m));
  Scan scan;
  scan.layout = layouts.get(n, static_cast<double>(aperture), res >= 0.0);
  scan.ranges_m.resize(n);
  scan.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = laser.ranges_m[i];
    const bool valid = std::isfinite(r) && r > 0.0 && r < laser.max_range_m;
    scan.ranges_m[i] = valid ? r : max_range;
    scan.valid[i] = valid ? 1 : 0;
  }
  scan.stamp_s = laser.stamp_s;
  scan.min_range_m = 0.0;
  scan.max_range_m = max_range;
  return scan;
}

Pose2D carmenSensorOnRobot(const CarmenLaser& laser) {
  const double res = laser.angular_resolution_rad;
  const double centre = laser.start_angle_rad + 0.5 * res * static_cast<double>(laser.ranges_m.size() - 1);
  return compose(laser.laser_on_robot, Pose2D{0.0, 0.0, centre});
}

}  // namespace lidarseg::logs
