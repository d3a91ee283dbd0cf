#pragma once
/// @file ScanSimulator.h
/// Simulated range scans of a World, with Gaussian range noise.

#include <cstdint>
#include <memory>
#include <random>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// What a simulated 2D range sensor looks like.
struct SensorModel {
  std::shared_ptr<const BeamLayout> layout;
  double max_range_m = 20.0;
  double min_range_m = 0.05;
  /// Standard deviation of the Gaussian noise added to each range (m).
  double range_sigma_m = 0.0;

  /// A SICK LMS100-like sensor: 270 deg at 0.5 deg (541 beams), 20 m, sigma 0.012 m.
  static SensorModel lms100();
};

/// Produces scans of a World seen from given sensor poses. Deterministic for a seed.
class ScanSimulator {
 public:
  ScanSimulator(SensorModel sensor, std::uint64_t seed);

  /// The scan seen by the sensor at `T_world_sensor`. Beams with no wall within the
  /// maximum range return max_range_m (invalid by the Scan convention).
  Scan scan(const World& world, const Pose2& T_world_sensor);

  const SensorModel& sensor() const { return sensor_; }

 private:
  SensorModel sensor_;
  std::mt19937_64 rng_;
};

}  // namespace lidarseg::sim
