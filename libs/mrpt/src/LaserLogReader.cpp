#include "lidarseg/mrpt/LaserLogReader.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <mrpt/system/datetime.h>

#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/mrpt/RawlogScanReader.h"

namespace lidarseg::mrpt_adapter {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A CARMEN laser line as an MRPT observation: evenly spaced beams centred on the
// sensor's x axis, the offset of the first beam carried by the sensor pose's yaw.
mrpt::obs::CObservation2DRangeScan::Ptr toObservation(const logs::CarmenLaser& l) {
  auto obs = mrpt::obs::CObservation2DRangeScan::Create();
  const std::size_t n = l.ranges_m.size();
  obs->sensorLabel = l.type;
  obs->timestamp = mrpt::Clock::fromDouble(l.stamp_s);
  const double res = l.angular_resolution_rad;
  obs->aperture = static_cast<float>(std::abs(res) * static_cast<double>(n - 1));
  obs->rightToLeft = res >= 0.0;
  obs->maxRange = static_cast<float>(l.max_range_m);
  const double centre = l.start_angle_rad + 0.5 * res * static_cast<double>(n - 1);
  const Pose2D sensor = compose(l.laser_on_robot, Pose2D{0.0, 0.0, centre});
  obs->sensorPose = mrpt::poses::CPose3D(sensor.x, sensor.y, 0.0, sensor.yaw, 0.0, 0.0);
  obs->resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = l.ranges_m[i];
    const bool valid = std::isfinite(r) && r > 0.0 && r < l.max_range_m;
    obs->setScanRange(i, valid ? static_cast<float>(r) : obs->maxRange);
    obs->setScanRangeValidity(i, valid);
  }
  return obs;
}

}  // namespace

LogFormat detectLogFormat(const std::string& path) {
  if (endsWith(path, ".rawlog") || endsWith(path, ".rawlog.gz")) return LogFormat::kRawlog;
  if (endsWith(path, ".clf") || endsWith(path, ".log") || endsWith(path, ".clf.gz") ||
      endsWith(path, ".log.gz")) {
    return LogFormat::kCarmen;
  }
  // Sniff: a CARMEN log is text; a rawlog starts with MRPT's binary object header.
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open log '" + path + "'");
  unsigned char head[2] = {0, 0};
  in.read(reinterpret_cast<char*>(head), 2);
  if (in.gcount() == 2 && head[0] == 0x1f && head[1] == 0x8b) return LogFormat::kRawlog;  // gz rawlog
  if (in.gcount() >= 1 && (head[0] == '#' || (head[0] >= 'A' && head[0] <= 'Z'))) return LogFormat::kCarmen;
  return LogFormat::kRawlog;
}

LaserLogReader::LaserLogReader(const std::string& path, const std::string& sensor)
    : path_(path), format_(detectLogFormat(path)) {
  if (format_ == LogFormat::kRawlog) {
    rawlog_ = std::make_unique<RawlogScanReader>(path, sensor);
  } else {
    logs::CarmenReaderOptions options;
    options.laser_type = sensor;
    carmen_ = std::make_unique<logs::CarmenLogReader>(path, options);
  }
}

LaserLogReader::~LaserLogReader() = default;

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
    auto scan = rawlog_->next();
    if (!scan) return std::nullopt;
    LaserRecord r;
    r.index = returned_++;
    r.where = path_ + ", entry " + std::to_string(scan->entry_index);
    r.stamp_s = mrpt::Clock::toDouble(scan->observation->timestamp);
    r.observation = scan->observation;
    if (scan->odometry) r.odometry = toPose2D(*scan->odometry);
    r.companions = std::move(scan->companions);
    return r;
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
    r.index = returned_++;
    r.where = path_ + ":" + std::to_string(laser->line);
    r.stamp_s = laser->stamp_s;
    r.observation = toObservation(*laser);
    // Raw wheel odometry: the last ODOM line when the log has them (corrected logs
    // rewrite the laser line's odometry fields), else the laser line's own fields.
    r.odometry = carmen_->lastOdometry() ? *carmen_->lastOdometry() : laser->robot_pose;
    r.log_pose = compose(laser->laser_pose, inverse(laser->laser_on_robot));
    return r;
  }
}

}  // namespace lidarseg::mrpt_adapter
