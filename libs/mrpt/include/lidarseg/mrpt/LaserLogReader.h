#pragma once
/// @file LaserLogReader.h
/// One reader for every supported laser log: MRPT rawlogs (both layouts) and CARMEN logs.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/obs/CObservation2DRangeScan.h>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/WarningTally.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::logs {
class ScanSource;
}

namespace lidarseg::mrpt_adapter {

class RawlogScanSource;

/// Format of a laser log.
enum class LogFormat { kRawlog, kCarmen };

/// One scan of a log: the core record (ranges in the sensor frame, mounting, stamp,
/// odometry, log pose) and the MRPT observation it came from, for the MRPT-side consumers
/// (MRPT ICP, the rawlog writer).
struct LaserRecord : ScanRecord {
  /// The rawlog's own observation of the scan; null for a CARMEN line, which is read into
  /// the core types with no MRPT in between (observationOf() makes one when an MRPT
  /// consumer needs it: the ICP baseline, a rawlog writer).
  mrpt::obs::CObservation2DRangeScan::Ptr observation;
  /// Other observations read since the previous scan (rawlogs only).
  std::vector<mrpt::obs::CObservation::Ptr> companions;
};

/// The record's scan as an MRPT observation: the rawlog's own, or for a CARMEN line one made
/// from the core record (float ranges, invalid beams flagged, the aperture, direction,
/// maximum range, stamp, label and sensor pose of the record), as a CARMEN-to-MRPT
/// converter would make it.
mrpt::obs::CObservation2DRangeScan::Ptr observationOf(const LaserRecord& record);

/// Pose of the record's laser on the robot in 3D: the rawlog observation's (its height, a
/// camera projection needs it), or the planar sensor_on_robot of a CARMEN line (z = 0).
mrpt::poses::CPose3D sensorPose3D(const LaserRecord& record);

/// Streams the scans of a laser log of either format, one sensor only: the log's
/// logs::ScanSource (CARMEN without MRPT, or a rawlog), each record with the MRPT
/// observations a rawlog holds for the MRPT-side consumers.
class LaserLogReader {
 public:
  /// Opens `path`: a rawlog when the name ends in .rawlog (or .rawlog.gz), CARMEN when it
  /// ends in .clf, .log or .log.gz / .clf.gz; otherwise the first bytes decide (text is
  /// CARMEN). `sensor`: rawlog sensor label or CARMEN line type (FLASER, RLASER,
  /// ROBOTLASER1); empty = the first laser scan met that parses.
  /// @throws std::runtime_error naming the file when it cannot be opened;
  /// std::invalid_argument naming the file when `sensor` is no CARMEN laser type.
  explicit LaserLogReader(const std::string& path, const std::string& sensor = {});
  ~LaserLogReader();

  /// The next scan, or std::nullopt at the end.
  /// @throws std::runtime_error naming the file and entry/line for a truncated or corrupt file,
  /// and at the end of a rawlog without a scan of the requested label, listing its labels.
  std::optional<LaserRecord> next();

  LogFormat format() const { return format_; }
  const std::string& path() const { return path_; }
  /// Share of the file read so far, 0 to 1 (compressed bytes for a gzip file): for a
  /// progress's time left when the number of scans is not known.
  double fractionRead() const;
  /// The sensor label or line type being read (known after the first scan).
  std::string sensor() const;
  /// Skipped lines/scans with their location (the first 100), and how many in all.
  const std::vector<std::string>& issues() const;
  std::size_t skipped() const;
  /// Messages about line types that were not understood ("UNKNOWN: 12 lines").
  std::vector<std::string> unknownTypes() const;
  /// Why the file gave no scan beyond its skipped lines (ScanSource::unreadScans()).
  std::string unreadScans() const;
  /// What was read but is worth a word (non-finite odometry dropped, a laser whose beam
  /// count, aperture or mounting changes), with its place; the first 100.
  std::vector<std::string> warnings() const;
  /// The warnings of warnings() and unknownTypes(), counted per kind in full (warnings()
  /// keeps the first 100 messages).
  WarningTally warningTally() const;

 private:
  std::string path_;
  LogFormat format_ = LogFormat::kRawlog;
  std::unique_ptr<logs::ScanSource> source_;
  RawlogScanSource* rawlog_ = nullptr;  // source_ when it is a rawlog: its MRPT observations
};

/// The format `path` is read as (see LaserLogReader).
LogFormat detectLogFormat(const std::string& path);

}  // namespace lidarseg::mrpt_adapter
