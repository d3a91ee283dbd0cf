#pragma once
/// @file CarmenLogReader.h
/// Streams the laser scans and odometry of a CARMEN log (plain or gzip).

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/logs/LineReader.h"

namespace lidarseg::logs {

/// One laser line of a CARMEN log (FLASER, RLASER or ROBOTLASER1).
struct CarmenLaser {
  std::string type;        ///< "FLASER", "RLASER" or "ROBOTLASER1"
  std::size_t line = 0;    ///< 1-based line number in the file
  double stamp_s = 0.0;    ///< the line's ipc timestamp, as written
  std::vector<double> ranges_m;
  /// Bearing of the first beam and increment between beams, in the laser frame (rad).
  double start_angle_rad = 0.0;
  double angular_resolution_rad = 0.0;
  /// Ranges at or above this mean "no return" (m).
  double max_range_m = 0.0;
  /// Laser pose written on the line (world frame; in "corrected" logs, the corrected pose).
  Pose2D laser_pose;
  /// Robot pose written on the line (FLASER: the wheel odometry; ROBOTLASER1: the robot pose).
  Pose2D robot_pose;
  /// Pose of the laser on the robot (from the PARAM offset or the line itself).
  Pose2D laser_on_robot;
};

/// Reading options.
struct CarmenReaderOptions {
  /// Laser line type to return (FLASER, RLASER or ROBOTLASER1); empty = the type of the
  /// first laser line that parses (a malformed line never decides it).
  std::string laser_type;
  /// Maximum range when no PARAM line gives one (m).
  double default_max_range_m = 50.0;
};

/// Whether `type` names a CARMEN laser line this reader parses (FLASER, RLASER, ROBOTLASER1).
bool isLaserType(const std::string& type);

/// Streaming reader of CARMEN logs: `FLASER n r1..rn x y theta odom_x odom_y odom_theta
/// ipc_ts host logger_ts`, `RLASER` (same), `ROBOTLASER1` (CARMEN 0.7 layout), `ODOM x y
/// theta tv rv accel ipc_ts host logger_ts`, `PARAM name value ...` and `#` comments.
///
/// Field of view: `PARAM laser_front_laser_fov`/`_resolution` (degrees) when present;
/// otherwise FLASER/RLASER cover 180 degrees from -90, with a resolution of 180/(n-1)
/// degrees for an odd beam count and 180/n for an even one (the SICK modes: 181/361 beams
/// include both ends, 180/360 do not). Maximum range: `PARAM robot_front_laser_max` (or
/// `laser_front_laser_max_range`) when present, else the option's default; SICK LMS error
/// codes (>= 81.83 m in cm mode, 32.763..32.767 m in mm mode) are "no return" too.
///
/// A malformed line (too few fields, a field that is not a number, a beam count that does
/// not match, fewer than 2 beams, a zero angular resolution or maximum range) is skipped
/// and reported in issues() with its line; unknown line types are skipped and counted. Known non-laser lines (NEFF, SYNC, TRUEPOS, GPS..., RAWLASER...)
/// are ignored.
class CarmenLogReader {
 public:
  /// @throws std::runtime_error naming the file when it cannot be opened;
  /// std::invalid_argument when options.laser_type is not a laser line type.
  explicit CarmenLogReader(const std::string& path, CarmenReaderOptions options = {});

  /// The next laser line of the selected type, or std::nullopt at the end of the file.
  /// @throws std::runtime_error naming the file and line for corrupt compressed data.
  std::optional<CarmenLaser> next();

  /// The last ODOM line read before the returned laser line (world frame), if any.
  const std::optional<Pose2D>& lastOdometry() const { return odometry_; }
  /// "file:line: message" for each skipped malformed line (the first 100), and the count.
  const std::vector<std::string>& issues() const { return issues_; }
  std::size_t malformedLines() const { return malformed_; }
  /// Lines of unknown type, by type.
  const std::map<std::string, std::size_t>& unknownTypes() const { return unknown_; }
  /// Lines of the laser types this reader does not read (RAWLASER1..4, ROBOTLASER2,
  /// POSITIONLASER, LASER1..5), by type: what a log without FLASER, RLASER or ROBOTLASER1 holds.
  const std::map<std::string, std::size_t>& unreadLaserLines() const { return unread_lasers_; }
  /// PARAM values read so far.
  const std::map<std::string, std::string>& params() const { return params_; }
  const std::string& laserType() const { return options_.laser_type; }
  const std::string& path() const { return reader_.path(); }
  /// Share of the file read so far, 0 to 1 (LineReader::fractionRead()).
  double fractionRead() const { return reader_.fractionRead(); }

 private:
  bool parseLaser(const std::string& type, const std::vector<std::string>& f, CarmenLaser& out);
  void report(const std::string& message);
  double paramDouble(const std::string& key, double fallback) const;

  LineReader reader_;
  CarmenReaderOptions options_;
  std::optional<Pose2D> odometry_;
  std::map<std::string, std::string> params_;
  std::vector<std::string> issues_;
  std::size_t malformed_ = 0;
  std::map<std::string, std::size_t> unknown_;
  std::map<std::string, std::size_t> unread_lasers_;
};

}  // namespace lidarseg::logs
