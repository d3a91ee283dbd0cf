#pragma once
/// @file Simulation.h
/// A robot driving a trajectory through a world with a lidar, wheel odometry and a camera:
/// the paper's experiment set-up (section IV.A) with ground truth.

#include <cstdint>
#include <string>
#include <vector>

#include "lidarseg/core/Scan.h"
#include "lidarseg/sim/CameraSimulator.h"
#include "lidarseg/sim/FeatureOracle.h"
#include "lidarseg/sim/OdometrySimulator.h"
#include "lidarseg/sim/ScanSimulator.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Every setting of a simulated run. The lidar is at the robot's origin (the robot frame
/// is the lidar frame in the plane), `lidar_z_m` above the floor.
struct SimulationParams {
  SensorModel sensor = SensorModel::lms100();
  /// Override of the profile's beam count and field of view (0: keep the profile's); the
  /// beams stay evenly spaced and centred on the sensor's x axis.
  std::size_t num_beams = 0;
  /// The largest num_beams accepted (the log readers' beam cap).
  static constexpr std::size_t kMaxBeams = 100000;
  double field_of_view_rad = 0.0;
  /// Each beam measured at its own time while the robot moves (paper IV.A); off: every
  /// beam of a scan from the pose at the scan's time.
  bool rolling_shutter = true;
  /// Which beam's instant the scans are stamped with (drivers differ); the ground truth and
  /// odometry poses are at the stamp, and the beam times relative to it.
  ScanStamp scan_stamp = ScanStamp::kFirst;
  double lidar_z_m = 0.3;
  PinholeCamera camera;
  SceneHeights heights;
  /// An image every this many scans; 0: no camera.
  std::size_t camera_every_scans = 25;
  OdometryNoise odometry;
  /// Time of the first scan (s since the Unix epoch): 2026-01-01 00:00:00 UTC.
  /// |start_time_s| <= kMaxAbsStartTimeS, so that stamps 1 ms apart stay distinct.
  double start_time_s = 1767225600.0;
  static constexpr double kMaxAbsStartTimeS = 9e9;  // 1e9 s below the readers' 1e10 s: room for the run
  std::uint64_t seed = 1;

  /// @throws std::invalid_argument naming the key.
  void validate() const;
};

/// The profile of that name. @throws std::invalid_argument listing the known names.
SensorModel sensorProfile(const std::string& name);

/// One time step of a simulated run.
struct SimulatedFrame {
  std::size_t index = 0;
  /// Time of the scan (s): its first, middle or last beam's (SimulationParams::scan_stamp);
  /// the beams are at stamp_s + scan.time_offsets_s.
  double stamp_s = 0.0;
  Scan scan;
  /// True robot pose at stamp_s (world frame).
  Pose2D T_world_robot;
  /// Wheel odometry pose at stamp_s (drifts from the truth).
  Pose2D odometry;
  /// Doors and corners the lidar sees, in the robot frame.
  std::vector<Feature> features;
  bool has_image = false;
  RgbImage image;
  std::vector<DoorBox> door_boxes;
};

/// Runs a simulation scan by scan; deterministic for a seed (same seed, same frames).
class Simulation {
 public:
  /// The most scans one simulation writes (10 h at 25 Hz): a trajectory planned at a
  /// crawl must not fill the disk.
  static constexpr std::size_t kMaxScans = 900000;
  /// @throws std::invalid_argument for invalid parameters or more than kMaxScans scans.
  Simulation(const World& world, const Trajectory& trajectory, const SimulationParams& params);

  /// Number of scans: one every 1/frequency seconds over the trajectory's duration.
  std::size_t numScans() const { return num_scans_; }
  const SimulationParams& params() const { return params_; }
  const FeatureOracle& features() const { return oracle_; }

  /// The next frame, in order. @throws std::out_of_range past the last scan.
  SimulatedFrame next();

 private:
  const World* world_;
  const Trajectory* trajectory_;
  SimulationParams params_;
  ScanSimulator lidar_;
  OdometrySimulator odometry_;
  CameraSimulator camera_;
  FeatureOracle oracle_;
  std::size_t num_scans_ = 0;
  std::size_t next_ = 0;
};

}  // namespace lidarseg::sim
