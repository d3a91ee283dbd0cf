#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LaserOdometry.h"

#include <cerrno>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <mrpt/system/datetime.h>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/logs/CarmenScan.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/mrpt/RawlogScanReader.h"

namespace lidarseg::mrpt_adapter {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The largest tilt (pitch or roll, rad) of a scan plane taken as horizontal: 0.6 deg, a
// range error below 0.01 %.
constexpr double kMaxTiltRad = 0.01;
constexpr std::size_t kMaxBeams = 100000;

bool finitePose(const mrpt::poses::CPose3D& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) && std::isfinite(p.yaw()) &&
         std::isfinite(p.pitch()) && std::isfinite(p.roll());
}

// What makes a rawlog scan unusable ("" when nothing). A laser mounted upside down is
// rewritten in place as the same scan seen by an upright laser (beams in the other order).
std::string checkRawlogScan(mrpt::obs::CObservation2DRangeScan& obs) {
  const double stamp = mrpt::Clock::toDouble(obs.timestamp);
  // A log without stamps (MRPT's INVALID_TIMESTAMP) runs on synthetic time steps.
  if (!std::isfinite(stamp)) return "timestamp is not finite";
  if (obs.timestamp != INVALID_TIMESTAMP && std::abs(stamp) > kMaxLogStampS) {
    return "timestamp " + numberText(stamp) + " s is beyond +-1e10 s (the year 2286): not a clock reading";
  }
  const std::size_t n = obs.getScanSize();
  if (n < 2 || n > kMaxBeams) return std::to_string(n) + " beams (need 2 to " + std::to_string(kMaxBeams) + ")";
  if (!std::isfinite(obs.aperture) || !(obs.aperture > 0.0f) || obs.aperture > 2.0f * static_cast<float>(kPi) + 1e-3f) {
    return "aperture " + numberText(static_cast<double>(obs.aperture)) + " rad is not in (0, 2 pi]";
  }
  if (!std::isfinite(obs.maxRange) || !(obs.maxRange > 0.0f)) return "maximum range is not finite and > 0";
  if (!finitePose(obs.sensorPose)) return "sensor pose is not finite";
  const auto R = obs.sensorPose.getRotationMatrix();
  const double up = R(2, 2);  // the sensor's z axis, in the robot's z
  if (std::abs(up) < std::cos(kMaxTiltRad)) {
    char text[160];
    std::snprintf(text, sizeof text, "scan plane tilted by %.3g deg (the planar pipeline needs it within %.2g deg of horizontal)",
                  std::acos(std::min(1.0, std::abs(up))) * kRadToDeg, kMaxTiltRad * kRadToDeg);
    return text;
  }
  const double yaw = std::atan2(R(1, 0), R(0, 0));  // where the sensor's x axis points
  if (up < 0.0) {
    // Upside down: the beams sweep the other way round the robot's z axis.
    obs.rightToLeft = !obs.rightToLeft;
  }
  const auto& p = obs.sensorPose;
  obs.sensorPose = mrpt::poses::CPose3D(p.x(), p.y(), p.z(), yaw, 0.0, 0.0);
  return "";
}

}  // namespace

mrpt::obs::CObservation2DRangeScan::Ptr observationOf(const LaserRecord& record) {
  if (record.observation) return record.observation;
  // A CARMEN line's scan: evenly spaced beams centred on the sensor's x axis (carmenScan()),
  // never refused here (an MRPT consumer takes what the core took).
  const Scan& scan = record.scan;
  const std::size_t n = scan.size();
  auto obs = mrpt::obs::CObservation2DRangeScan::Create();
  obs->sensorLabel = record.sensor;
  obs->timestamp = mrpt::Clock::fromDouble(record.stamp_s);
  if (n >= 2 && scan.layout) {
    const double first = scan.layout->angle(0), last = scan.layout->angle(n - 1);
    obs->aperture = static_cast<float>(std::abs(last - first));
    obs->rightToLeft = last >= first;
  }
  obs->maxRange = static_cast<float>(scan.max_range_m);
  const Pose2D& s = record.sensor_on_robot;
  obs->sensorPose = mrpt::poses::CPose3D(s.x, s.y, 0.0, s.yaw, 0.0, 0.0);
  obs->resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    // A CARMEN line's own test (finite, > 0, < its maximum range); a scan made without
    // flags (by a program, the simulator) has only the core's.
    const bool valid = scan.valid.empty() ? scan.beamValid(i) : scan.valid[i] != 0;
    obs->setScanRange(i, valid ? static_cast<float>(scan.ranges_m[i]) : obs->maxRange);
    obs->setScanRangeValidity(i, valid);
  }
  return obs;
}

mrpt::poses::CPose3D sensorPose3D(const LaserRecord& record) {
  if (record.observation) return record.observation->sensorPose;
  const Pose2D& s = record.sensor_on_robot;
  return mrpt::poses::CPose3D(s.x, s.y, 0.0, s.yaw, 0.0, 0.0);
}

void LaserLogReader::watchGeometry(LaserRecord& r) {
  if (r.odometry && !(std::isfinite(r.odometry->x) && std::isfinite(r.odometry->y) && std::isfinite(r.odometry->yaw))) {
    warn(r.where + ": wheel odometry is not finite; not used");
    r.odometry.reset();
  }
  const BeamLayout& layout = *r.scan.layout;
  const Geometry g{layout.size(), layout.angle(0), layout.angle(layout.size() - 1), r.sensor_on_robot.x,
                   r.sensor_on_robot.y, r.sensor_on_robot.yaw};
  if (!geometry_) {
    geometry_ = g;
  } else if (!geometry_changed_ && !(g == *geometry_)) {
    geometry_changed_ = true;
    warn(r.where + ": the laser '" + r.sensor + "' changes its beam count, aperture or mounting (" +
         std::to_string(geometry_->beams) + " -> " + std::to_string(g.beams) + " beams); each scan is taken as it is");
  }
}

std::vector<std::string> LaserLogReader::warnings() const {
  std::vector<std::string> out = warnings_;
  if (rawlog_) {
    for (const auto& m : rawlog_->skippedEntries()) out.push_back(m);
    if (rawlog_->skippedEntryCount() > rawlog_->skippedEntries().size()) {
      out.push_back(path_ + ": " + std::to_string(rawlog_->skippedEntryCount()) +
                    " entries skipped for a corrupt JPEG image in all");
    }
    for (const auto& m : rawlog_->droppedOdometry()) out.push_back(m);
    if (rawlog_->droppedOdometryCount() > rawlog_->droppedOdometry().size()) {
      out.push_back(path_ + ": " + std::to_string(rawlog_->droppedOdometryCount()) + " non-finite odometry values in all");
    }
    if (rawlog_->droppedCompanions() > 0) {
      out.push_back(path_ + ": " + std::to_string(rawlog_->droppedCompanions()) +
                    " observations not kept: more than " + std::to_string(RawlogScanReader::kMaxCompanions) +
                    " came between two scans of '" + rawlog_->sensorLabel() + "' (only the latest are kept)");
    }
  }
  return out;
}

void LaserLogReader::warn(const std::string& message) {
  if (warnings_.size() < 100) warnings_.push_back(message);
  tally_.add(message);
}

WarningTally LaserLogReader::warningTally() const {
  WarningTally out = tally_;
  if (rawlog_) {
    out.merge(rawlog_->skippedEntriesTally());
    out.merge(rawlog_->droppedOdometryTally());
    if (rawlog_->droppedCompanions() > 0) {
      out.add(path_ + ": " + std::to_string(rawlog_->droppedCompanions()) + " observations not kept: more than " +
              std::to_string(RawlogScanReader::kMaxCompanions) + " came between two scans of '" +
              rawlog_->sensorLabel() + "' (only the latest are kept)");
    }
  }
  for (const auto& m : unknownTypes()) out.add(m);
  return out;
}

LogFormat detectLogFormat(const std::string& path) {
  {
    // What cannot be a log is said plainly, before any reader reports it as corrupt data
    // ("adir:1: corrupt or truncated compressed data (Is a directory)").
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw std::runtime_error("log '" + path + "' is a directory");
  }
  if (endsWith(path, ".rawlog") || endsWith(path, ".rawlog.gz")) return LogFormat::kRawlog;
  if (endsWith(path, ".clf") || endsWith(path, ".log") || endsWith(path, ".clf.gz") ||
      endsWith(path, ".log.gz")) {
    return LogFormat::kCarmen;
  }
  // A pipe or a device cannot be sniffed without losing what was read: such a stream is
  // taken as text (CARMEN); a rawlog is read from a file.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) return LogFormat::kCarmen;
  // Sniff: a CARMEN log is text whose first line starts with a comment or a line type; a
  // rawlog starts with gzip's magic or MRPT's object header, whose first byte is 0x80 or more
  // (0x80 | the class name's length), never whitespace. CARMEN lines may be indented or
  // follow blank lines, so whitespace is skipped (at most kSniffBytes bytes) before the first
  // character decides.
  constexpr std::streamsize kSniffBytes = 4096;
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;  // the reason (no such file, a symbolic link loop, permission)
    throw std::runtime_error("cannot open log '" + path + "'" + (error != 0 ? ": " + std::string(std::strerror(error)) : ""));
  }
  unsigned char head[2] = {0, 0};
  in.read(reinterpret_cast<char*>(head), 2);
  if (in.gcount() == 2 && head[0] == 0x1f && head[1] == 0x8b) return LogFormat::kRawlog;  // gz rawlog
  in.clear();
  in.seekg(0);
  for (std::streamsize n = 0; n < kSniffBytes; ++n) {
    const int c = in.get();
    if (c == std::char_traits<char>::eof()) break;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f') continue;
    return c == '#' || (c >= 'A' && c <= 'Z') ? LogFormat::kCarmen : LogFormat::kRawlog;
  }
  return LogFormat::kRawlog;
}

LaserLogReader::LaserLogReader(const std::string& path, const std::string& sensor)
    : path_(path), format_(detectLogFormat(path)) {
  if (format_ == LogFormat::kRawlog) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
      // MRPT's reader and the gzip end check open the file more than once: a pipe would
      // lose data or block.
      throw std::runtime_error("rawlog '" + path + "' is not a regular file (a pipe?): give the file itself");
    }
    rawlog_ = std::make_unique<RawlogScanReader>(path, sensor);
  } else {
    logs::CarmenReaderOptions options;
    options.laser_type = sensor;
    carmen_ = std::make_unique<logs::CarmenLogReader>(path, options);
  }
}

LaserLogReader::~LaserLogReader() = default;

double LaserLogReader::fractionRead() const {
  return rawlog_ ? rawlog_->fractionRead() : carmen_->fractionRead();
}

std::string LaserLogReader::sensor() const {
  return rawlog_ ? rawlog_->sensorLabel() : carmen_->laserType();
}

void LaserLogReader::note(const std::string& message) {
  ++skipped_;
  if (issues_.size() < 100) issues_.push_back(message);
}

std::vector<std::string> LaserLogReader::unknownTypes() const {
  std::vector<std::string> out;
  if (carmen_) {
    for (const auto& [type, n] : carmen_->unknownTypes()) {
      out.push_back(path_ + ": " + std::to_string(n) + " line(s) of unknown type '" + type + "' skipped");
    }
  }
  return out;
}

std::optional<LaserRecord> LaserLogReader::next() {
  if (rawlog_) {
    while (true) {
      auto scan = rawlog_->next();
      if (!scan) return std::nullopt;
      const std::string where = path_ + ", entry " + std::to_string(scan->entry_index);
      const std::string problem = checkRawlogScan(*scan->observation);
      if (!problem.empty()) {
        note(where + ": " + problem + "; scan skipped");
        continue;
      }
      LaserRecord r;
      r.where = where;
      r.stamp_s = mrpt::Clock::toDouble(scan->observation->timestamp);
      r.observation = scan->observation;
      r.sensor = r.observation->sensorLabel;
      try {  // a scan the core cannot represent is skipped with its place, as before
        r.scan = converter_.convert(*r.observation);
      } catch (const std::invalid_argument& e) {
        note(where + ": " + e.what() + "; scan skipped");
        continue;
      }
      r.scan.stamp_s = r.stamp_s;
      r.sensor_on_robot = sensorOnRobot(*r.observation);
      if (scan->odometry) r.odometry = toPose2D(*scan->odometry);
      r.companions = std::move(scan->companions);
      watchGeometry(r);
      r.index = returned_++;
      return r;
    }
  }
  while (true) {
    const std::size_t malformed_before = carmen_->malformedLines();
    auto laser = carmen_->next();
    // Lines the CARMEN reader skipped become this reader's issues too.
    for (std::size_t k = malformed_before; k < carmen_->malformedLines(); ++k) {
      note(k < carmen_->issues().size() ? carmen_->issues()[k] : path_ + ": malformed line");
    }
    if (!laser) return std::nullopt;
    if (laser->ranges_m.size() < 2 || !(laser->angular_resolution_rad != 0.0) ||
        !(laser->max_range_m > 0.0)) {
      note(path_ + ":" + std::to_string(laser->line) + ": " + laser->type + " with " +
           std::to_string(laser->ranges_m.size()) + " beam(s) (need 2 or more) skipped");
      continue;
    }
    LaserRecord r;
    r.where = path_ + ":" + std::to_string(laser->line);
    r.stamp_s = laser->stamp_s;
    r.sensor = laser->type;
    // The core scan straight from the line (no MRPT observation in between). A line the core
    // cannot represent (an aperture overflowing to infinity) is skipped with its place.
    try {
      r.scan = logs::carmenScan(*laser, carmen_layouts_);
    } catch (const std::invalid_argument& e) {
      note(r.where + ": " + e.what() + "; line skipped");
      continue;
    }
    r.index = returned_++;
    r.sensor_on_robot = logs::carmenSensorOnRobot(*laser);
    // Raw wheel odometry: the last ODOM line when the log has them (corrected logs
    // rewrite the laser line's odometry fields), else the laser line's own fields.
    r.odometry = carmen_->lastOdometry() ? *carmen_->lastOdometry() : laser->robot_pose;
    r.log_pose = compose(laser->laser_pose, inverse(laser->laser_on_robot));
    watchGeometry(r);
    return r;
  }
}

}  // namespace lidarseg::mrpt_adapter
