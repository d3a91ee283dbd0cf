#include "lidarseg/sim/ScanSimulator.h"
#include "lidarseg/core/Angles.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace lidarseg::sim {

namespace {
// An evenly spaced sensor centred on x, from its data sheet's figures.
SensorModel profile(std::size_t beams, double fov_deg, double max_range_m, double min_range_m,
                    double sigma_m, double frequency_hz) {
  SensorModel m;
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(beams, fov_deg * kDegToRad));
  m.max_range_m = max_range_m;
  m.min_range_m = min_range_m;
  m.range_sigma_m = sigma_m;
  m.frequency_hz = frequency_hz;
  return m;
}
}  // namespace

SensorModel SensorModel::lms100() { return profile(541, 270.0, 20.0, 0.05, 0.012, 50.0); }

SensorModel SensorModel::utm30lx() {
  SensorModel m = profile(1081, 270.0, 30.0, 0.1, 0.01, 40.0);
  m.far_range_m = 10.0;
  m.far_range_sigma_m = 0.03;
  return m;
}

SensorModel SensorModel::sick180() { return profile(181, 180.0, 80.0, 0.05, 0.01, 75.0); }

SensorModel SensorModel::rplidar360() {
  SensorModel m;
  // A full turn at 1 degree, centred on x as MRPT describes it (aperture 359 degrees: beams
  // from -179.5 to +179.5 degrees), so its scans convert to CObservation2DRangeScan.
  m.layout = std::make_shared<BeamLayout>(BeamLayout::centred(360, 2.0 * kPi * 359.0 / 360.0));
  m.max_range_m = 12.0;
  m.min_range_m = 0.15;
  m.range_sigma_m = 0.02;
  m.far_range_m = 4.0;
  m.far_range_sigma_m = 0.05;
  m.frequency_hz = 5.5;
  return m;
}

ScanSimulator::ScanSimulator(const World& world, SensorModel sensor, std::uint64_t seed)
    : sensor_(std::move(sensor)), caster_(world), rng_(seed) {
  if (!sensor_.layout) throw std::invalid_argument("ScanSimulator: sensor has no beam layout");
  if (!(sensor_.frequency_hz > 0.0)) throw std::invalid_argument("ScanSimulator: frequency_hz must be > 0");
}

double ScanSimulator::beamPeriod() const {
  return sensor_.layout->meanIncrement() / (2.0 * kPi * sensor_.frequency_hz);
}

double ScanSimulator::sweepDuration() const {
  const std::size_t n = sensor_.layout->size();
  return n > 1 ? beamPeriod() * static_cast<double>(n - 1) : 0.0;
}

Scan ScanSimulator::scan(const Pose2D& T_world_sensor) { return scan(T_world_sensor, T_world_sensor); }

Scan ScanSimulator::scan(const Pose2D& first, const Pose2D& last) {
  const BeamLayout& layout = *sensor_.layout;
  const std::size_t n = layout.size();
  Scan s;
  s.layout = sensor_.layout;
  s.min_range_m = sensor_.min_range_m;
  s.max_range_m = sensor_.max_range_m;
  s.ranges_m.resize(n);
  s.time_offsets_s.resize(n);
  const double period = beamPeriod();
  const double yaw_span = std::remainder(last.yaw - first.yaw, 2.0 * kPi);
  const double inv = n > 1 ? 1.0 / static_cast<double>(n - 1) : 0.0;
  // The heading turns by a constant step per beam: rotate (cos, sin) instead of calling
  // the trigonometric functions per beam.
  double cy = std::cos(first.yaw), sy = std::sin(first.yaw);
  const double step_c = std::cos(yaw_span * inv), step_s = std::sin(yaw_span * inv);
  for (std::size_t i = 0; i < n; ++i) {
    // The sensor pose at this beam's instant (linear in time within one sweep).
    const double f = static_cast<double>(i) * inv;
    const Eigen::Vector2d origin(first.x + f * (last.x - first.x), first.y + f * (last.y - first.y));
    const double cb = layout.cosine(i), sb = layout.sine(i);
    const Eigen::Vector2d dir(cy * cb - sy * sb, sy * cb + cy * sb);
    const double next_cy = cy * step_c - sy * step_s;
    sy = sy * step_c + cy * step_s;
    cy = next_cy;
    const RayHit hit = caster_.cast(origin, dir, sensor_.max_range_m);
    double r = sensor_.max_range_m;
    if (hit.hit()) {
      r = hit.range + sensor_.sigmaAt(hit.range) * unit_noise_(rng_);
      // Noise never turns a return into "no return" or a negative range.
      r = std::min(std::max(r, 0.0), std::nextafter(sensor_.max_range_m, 0.0));
    }
    s.ranges_m[i] = r;
    s.time_offsets_s[i] = static_cast<double>(i) * period;
  }
  return s;
}

}  // namespace lidarseg::sim
