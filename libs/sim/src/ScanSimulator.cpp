#include "lidarseg/sim/ScanSimulator.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace lidarseg::sim {

SensorModel SensorModel::lms100() {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  SensorModel m;
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(541, 270.0 * kDeg));
  m.max_range_m = 20.0;
  m.min_range_m = 0.05;
  m.range_sigma_m = 0.012;
  m.frequency_hz = 50.0;
  return m;
}

SensorModel SensorModel::utm30lx() {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  SensorModel m;
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(1081, 270.0 * kDeg));
  m.max_range_m = 30.0;
  m.min_range_m = 0.1;
  m.range_sigma_m = 0.01;
  m.far_range_m = 10.0;
  m.far_range_sigma_m = 0.03;
  m.frequency_hz = 40.0;
  return m;
}

SensorModel SensorModel::sick180() {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  SensorModel m;
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(181, 180.0 * kDeg));
  m.max_range_m = 80.0;
  m.min_range_m = 0.05;
  m.range_sigma_m = 0.01;
  m.frequency_hz = 75.0;
  return m;
}

ScanSimulator::ScanSimulator(SensorModel sensor, std::uint64_t seed)
    : sensor_(std::move(sensor)), rng_(seed) {
  if (!sensor_.layout) throw std::invalid_argument("ScanSimulator: sensor has no beam layout");
}

Scan ScanSimulator::scan(const World& world, const Pose2& T_world_sensor) {
  const BeamLayout& layout = *sensor_.layout;
  Scan s;
  s.layout = sensor_.layout;
  s.min_range_m = sensor_.min_range_m;
  s.max_range_m = sensor_.max_range_m;
  s.ranges_m.resize(layout.size());
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Vector2d origin(T_world_sensor.x, T_world_sensor.y);
  for (std::size_t i = 0; i < layout.size(); ++i) {
    const double a = T_world_sensor.yaw + layout.angle(i);
    const double hit = world.castRay(origin, {std::cos(a), std::sin(a)});
    double r = sensor_.max_range_m;
    if (hit < sensor_.max_range_m) {
      r = hit + sensor_.sigmaAt(hit) * noise(rng_);
      // Noise never turns a return into "no return" or a negative range.
      r = std::min(std::max(r, 0.0), std::nextafter(sensor_.max_range_m, 0.0));
    }
    s.ranges_m[i] = r;
  }
  return s;
}

}  // namespace lidarseg::sim
