#include "lidarseg/mrpt/RawlogScanSource.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <mrpt/system/datetime.h>

#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/LaserOdometry.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/mrpt/RawlogScanReader.h"

namespace lidarseg::mrpt_adapter {

namespace {

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
  if (std::max({std::abs(obs.sensorPose.x()), std::abs(obs.sensorPose.y()), std::abs(obs.sensorPose.z())}) > kMaxLogCoordinate) {
    return "sensor pose (" + numberText(obs.sensorPose.x()) + ", " + numberText(obs.sensorPose.y()) + ", " +
           numberText(obs.sensorPose.z()) + ") is beyond +-1e6 m: not a mounting";
  }
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

RawlogScanSource::RawlogScanSource(const std::string& path, const std::string& label) : ScanSource(path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
    // MRPT's reader and the gzip end check open the file more than once: a pipe would lose
    // data or block.
    throw std::runtime_error("rawlog '" + path + "' is not a regular file (a pipe?): give the file itself");
  }
  reader_ = std::make_unique<RawlogScanReader>(path, label);
}

RawlogScanSource::~RawlogScanSource() = default;

std::string RawlogScanSource::sensor() const { return reader_->sensorLabel(); }

double RawlogScanSource::fractionRead() const { return reader_->fractionRead(); }

std::optional<ScanRecord> RawlogScanSource::read() {
  while (true) {
    auto scan = reader_->next();
    if (!scan) return std::nullopt;
    const std::string where = path() + ", entry " + std::to_string(scan->entry_index);
    const std::string problem = checkRawlogScan(*scan->observation);
    if (!problem.empty()) {
      note(where + ": " + problem + "; scan skipped");
      continue;
    }
    ScanRecord r;
    r.where = where;
    r.stamp_s = mrpt::Clock::toDouble(scan->observation->timestamp);
    r.sensor = scan->observation->sensorLabel;
    try {  // a scan the core cannot represent is skipped with its place
      r.scan = converter_.convert(*scan->observation);
    } catch (const std::invalid_argument& e) {
      note(where + ": " + e.what() + "; scan skipped");
      continue;
    }
    r.scan.stamp_s = r.stamp_s;
    r.sensor_on_robot = sensorOnRobot(*scan->observation);
    if (scan->odometry) r.odometry = toPose2D(*scan->odometry);
    observation_ = std::move(scan->observation);
    companions_ = std::move(scan->companions);
    return r;
  }
}

std::string RawlogScanSource::droppedCompanionsMessage() const {
  return path() + ": " + std::to_string(reader_->droppedCompanions()) + " observations not kept: more than " +
         std::to_string(RawlogScanReader::kMaxCompanions) + " came between two scans of '" + reader_->sensorLabel() +
         "' (only the latest are kept)";
}

std::vector<std::string> RawlogScanSource::sourceWarnings() const {
  std::vector<std::string> out;
  for (const auto& m : reader_->skippedEntries()) out.push_back(m);
  if (reader_->skippedEntryCount() > reader_->skippedEntries().size()) {
    out.push_back(path() + ": " + std::to_string(reader_->skippedEntryCount()) +
                  " entries skipped for a corrupt JPEG image in all");
  }
  for (const auto& m : reader_->droppedOdometry()) out.push_back(m);
  if (reader_->droppedOdometryCount() > reader_->droppedOdometry().size()) {
    out.push_back(path() + ": " + std::to_string(reader_->droppedOdometryCount()) + " non-finite odometry values in all");
  }
  if (reader_->droppedCompanions() > 0) out.push_back(droppedCompanionsMessage());
  return out;
}

WarningTally RawlogScanSource::sourceWarningTally() const {
  WarningTally out;
  out.merge(reader_->skippedEntriesTally());
  out.merge(reader_->droppedOdometryTally());
  if (reader_->droppedCompanions() > 0) out.add(droppedCompanionsMessage());
  return out;
}

}  // namespace lidarseg::mrpt_adapter
