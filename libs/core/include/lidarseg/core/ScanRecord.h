#pragma once
/// @file ScanRecord.h
/// One scan of a log as the algorithms need it, whatever the log's format: the ranges in the
/// sensor frame, the sensor's mounting on the robot, and what the log says of the robot at
/// that time.

#include <cstddef>
#include <optional>
#include <string>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Scan.h"

namespace lidarseg {

/// The largest magnitude a log's pose field may have (m, or rad for a heading): 1000 km. A
/// reader refuses larger values as corrupt, as it refuses a non-finite one (1e308 would
/// overflow every later difference of poses).
constexpr double kMaxLogCoordinate = 1e6;
/// The largest magnitude of a relative pose the odometry takes (an odometry increment, a
/// sensor's pose on the robot, an initial estimate; m, rad): 10 000 km, above any
/// difference of two poses within kMaxLogCoordinate, so that what a reader accepts is never
/// refused later.
constexpr double kMaxRelativeCoordinate = 1e7;

/// One scan of a log (built by a log reader, e.g. mrpt_adapter::LaserLogReader).
struct ScanRecord {
  /// 0-based index of the scan among the scans returned.
  std::size_t index = 0;
  /// Where the scan is in the file, for messages: "file, entry 12" or "file:345".
  std::string where;
  /// The sensor: a rawlog's sensor label, a CARMEN line's type (FLASER, ...).
  std::string sensor;
  /// Time of the scan in the log's clock (s); CARMEN: the line's ipc timestamp.
  double stamp_s = 0.0;
  /// The ranges, sensor frame (x forward, y left; m), `scan.stamp_s` = stamp_s.
  Scan scan;
  /// Pose of the sensor on the robot (T_robot_sensor; m, rad), planar.
  Pose2D sensor_on_robot;
  /// Wheel odometry of the robot (odometry frame), when the log has it.
  std::optional<Pose2D> odometry;
  /// Robot pose written in the log beside the scan (CARMEN laser lines: in "corrected"
  /// logs, the corrected pose), usable as a reference.
  std::optional<Pose2D> log_pose;
};

}  // namespace lidarseg
