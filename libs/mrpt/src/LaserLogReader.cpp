#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/logs/CompressedInput.h"
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
#include "lidarseg/logs/CarmenScanSource.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/PoseConversion.h"
#include "lidarseg/mrpt/RawlogScanSource.h"

namespace lidarseg::mrpt_adapter {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
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
  // The first bytes of the content (decompressed: a gzip file may hold either format).
  std::string head(static_cast<std::size_t>(kSniffBytes), '\0');
  std::size_t got = 0;
  try {
    logs::CompressedInput content(path);
    while (got < head.size()) {
      const std::size_t n = content.read(head.data() + got, head.size() - got);
      if (n == 0) break;
      got += n;
    }
  } catch (const std::runtime_error&) {
    // A damaged gzip file: read as a rawlog, whose reader names the damage.
  }
  // An editor's UTF-8 byte-order mark before a text log's first line.
  const std::size_t start = head.compare(0, 3, "\xEF\xBB\xBF") == 0 && got >= 3 ? 3 : 0;
  for (std::size_t n = start; n < got; ++n) {
    const unsigned char c = static_cast<unsigned char>(head[n]);
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f') continue;
    return c == '#' || (c >= 'A' && c <= 'Z') ? LogFormat::kCarmen : LogFormat::kRawlog;
  }
  return LogFormat::kRawlog;
}

LaserLogReader::LaserLogReader(const std::string& path, const std::string& sensor)
    : path_(path), format_(detectLogFormat(path)) {
  if (format_ == LogFormat::kRawlog) {
    auto rawlog = std::make_unique<RawlogScanSource>(path, sensor);
    rawlog_ = rawlog.get();
    source_ = std::move(rawlog);
  } else {
    source_ = std::make_unique<logs::CarmenScanSource>(path, sensor);
  }
}

LaserLogReader::~LaserLogReader() = default;

double LaserLogReader::fractionRead() const { return source_->fractionRead(); }
std::string LaserLogReader::sensor() const { return source_->sensor(); }
const std::vector<std::string>& LaserLogReader::issues() const { return source_->issues(); }
std::size_t LaserLogReader::skipped() const { return source_->skipped(); }
std::vector<std::string> LaserLogReader::unknownTypes() const { return source_->unknownTypes(); }
std::string LaserLogReader::unreadScans() const { return source_->unreadScans(); }
std::vector<std::string> LaserLogReader::warnings() const { return source_->warnings(); }
WarningTally LaserLogReader::warningTally() const { return source_->warningTally(); }

std::optional<LaserRecord> LaserLogReader::next() {
  std::optional<ScanRecord> scan = source_->next();
  if (!scan) return std::nullopt;
  LaserRecord r;
  static_cast<ScanRecord&>(r) = std::move(*scan);
  if (rawlog_ != nullptr) {
    r.observation = rawlog_->lastObservation();
    r.companions = rawlog_->takeCompanions();
  }
  return r;
}

}  // namespace lidarseg::mrpt_adapter
