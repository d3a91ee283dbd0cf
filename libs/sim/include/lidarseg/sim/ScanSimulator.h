#pragma once
/// @file ScanSimulator.h
/// Simulated range scans of a World, with Gaussian range noise.

#include <cstdint>
#include <limits>
#include <memory>
#include <random>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// What a simulated 2D range sensor looks like.
struct SensorModel {
  std::shared_ptr<const BeamLayout> layout;
  double max_range_m = 20.0;
  double min_range_m = 0.05;
  /// Standard deviation of the Gaussian noise added to each range (m)...
  double range_sigma_m = 0.0;
  /// ... and beyond this range (m), this one instead (data sheets often give two figures).
  double far_range_m = std::numeric_limits<double>::infinity();
  double far_range_sigma_m = 0.0;

  /// Noise standard deviation for a true range r (m).
  double sigmaAt(double r) const { return r > far_range_m ? far_range_sigma_m : range_sigma_m; }

  /// SICK LMS100: 270 deg at 0.5 deg (541 beams), 50 Hz, 20 m, sigma 0.012 m.
  static SensorModel lms100();
  /// Hokuyo UTM-30LX: 270 deg at 0.25 deg (1081 beams), 40 Hz, 30 m, sigma 0.01 m under
  /// 10 m and 0.03 m beyond.
  static SensorModel utm30lx();
  /// A 180-degree scanner at 1 deg (181 beams), 80 m, sigma 0.01 m (SICK LMS200-like).
  static SensorModel sick180();
  /// A low-cost spinning 360-degree scanner (RPLIDAR A1-like): a full turn at 1 deg (360
  /// beams from -179.5 to +179.5 deg), 5.5 Hz, 0.15-12 m, sigma 0.02 m under 4 m and 0.05 m
  /// beyond. Its sweep lasts the whole period (0.18 s): a robot turning at 1 rad/s turns
  /// 0.18 rad during one scan.
  static SensorModel rplidar360();

  /// Scan frequency (Hz): the time between beams is 1 / (frequency * beams per turn).
  double frequency_hz = 50.0;
};

/// Produces scans of a World seen from given sensor poses. Deterministic for a seed.
class ScanSimulator {
 public:
  /// Indexes the world's walls (the world may change afterwards; this keeps a snapshot).
  ScanSimulator(const World& world, SensorModel sensor, std::uint64_t seed);

  /// The scan seen by a sensor standing still at `T_world_sensor`. Beams with no wall
  /// within the maximum range return max_range_m (invalid by the Scan convention).
  Scan scan(const Pose2D& T_world_sensor);

  /// The scan of a moving sensor ("rolling shutter", paper IV.A): beam i is measured at
  /// time_offsets_s[i] = i * beam period after the first beam, from the sensor pose
  /// interpolated between `T_world_sensor_first` (first beam) and `T_world_sensor_last`
  /// (last beam). The ranges are those a real spinning scanner reports: each in the
  /// sensor frame of its own instant.
  Scan scan(const Pose2D& T_world_sensor_first, const Pose2D& T_world_sensor_last);

  /// Time between consecutive beams (s): beam spacing / (2 pi frequency).
  double beamPeriod() const;
  /// Duration of one sweep, first to last beam (s).
  double sweepDuration() const;

  const SensorModel& sensor() const { return sensor_; }

 private:
  SensorModel sensor_;
  RayCaster caster_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_noise_{0.0, 1.0};
};

}  // namespace lidarseg::sim
