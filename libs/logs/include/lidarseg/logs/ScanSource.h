#pragma once
/// @file ScanSource.h
/// The one interface every log format is read through: a stream of core ScanRecord values
/// (ranges in the sensor frame, mounting, stamp, wheel odometry, log pose), with the checks
/// every format shares (a scan's odometry, a laser whose geometry changes) and what was
/// skipped or worth a word, each with its place in the file. The CARMEN source needs no
/// MRPT (CarmenScanSource); the rawlog source lives in the MRPT adapter
/// (mrpt_adapter::RawlogScanSource). The tools read through mrpt_adapter::LaserLogReader,
/// which opens the right source and adds MRPT's observations for MRPT-side outputs.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/WarningTally.h"

namespace lidarseg::logs {

/// A log's scans, one sensor, in file order.
class ScanSource {
 public:
  explicit ScanSource(std::string path) : path_(std::move(path)) {}
  virtual ~ScanSource() = default;
  /// How far a laser's mounting may move on the robot between scans and count as unchanged:
  /// 5 mm and 0.25 degree: above the difference of two mountings each obtained as the
  /// difference of two poses printed with 3 decimals (each off by up to 1.4 mm and 0.001 rad,
  /// so two by up to about 3 mm and 0.11 degree; CARMEN's own logger prints 6) and below any
  /// real change of mounting (centimetres, degrees).
  static constexpr double kMountingToleranceM = 5e-3;
  static constexpr double kMountingToleranceRad = 0.25 * 3.14159265358979323846 / 180.0;
  ScanSource(const ScanSource&) = delete;
  ScanSource& operator=(const ScanSource&) = delete;

  /// The next usable scan (`index` counting the scans returned), or std::nullopt at the end.
  /// Unusable scans are skipped and listed in issues(); a record's non-finite wheel odometry
  /// is dropped with a warning; the first change of the laser's beam count, aperture or
  /// mounting is warned (a mounting within kMountingToleranceM and kMountingToleranceRad
  /// of the first is the same: CARMEN's ROBOTLASER1 gives it only as the difference of two
  /// poses rounded to its printed digits, which varies as the robot turns).
  /// @throws std::runtime_error naming the file and line/entry for a truncated or corrupt file.
  std::optional<ScanRecord> next();

  /// The file read.
  const std::string& path() const { return path_; }
  /// The sensor label or line type read (known after the first scan).
  virtual std::string sensor() const = 0;
  /// Share of the file read so far, 0 to 1 (compressed bytes for a gzip file).
  virtual double fractionRead() const = 0;

  /// Skipped lines/scans with their place (the first 100), and how many in all.
  const std::vector<std::string>& issues() const { return issues_; }
  std::size_t skipped() const { return skipped_; }
  /// Line types or objects not understood ("FILE: 12 line(s) of unknown type 'X' skipped").
  virtual std::vector<std::string> unknownTypes() const { return {}; }
  /// Why a file gave no scan beyond its skipped lines (e.g. only laser lines of a type the
  /// format's reader does not read); empty when there is nothing to add.
  virtual std::string unreadScans() const { return {}; }
  /// What was read but is worth a word, with its place; the first 100 of this source's own
  /// and the format's (sourceWarnings()).
  std::vector<std::string> warnings() const;
  /// Every warning of warnings() and unknownTypes(), counted per kind in full.
  WarningTally warningTally() const;

 protected:
  /// The format's next scan, before the shared checks; std::nullopt at the end. `index` is
  /// set by next().
  virtual std::optional<ScanRecord> read() = 0;
  /// The format's own warnings (after this source's), and their tally in full.
  virtual std::vector<std::string> sourceWarnings() const { return {}; }
  virtual WarningTally sourceWarningTally() const { return {}; }
  /// A skipped line or scan, "WHERE: what; scan skipped".
  void note(const std::string& message);
  /// Something worth a word, with its place.
  void warn(const std::string& message);

 private:
  void watch(ScanRecord& record);
  struct Geometry {
    std::size_t beams;
    double first_angle, last_angle;  // of the scan's layout (sensor frame)
    double x, y, yaw;                // sensor_on_robot
    /// The same layout, and the same mounting within the tolerances.
    bool same(const Geometry& o) const;
  };
  std::string path_;
  std::optional<Geometry> geometry_;
  bool geometry_changed_ = false;
  std::size_t returned_ = 0;
  std::size_t skipped_ = 0;
  std::vector<std::string> issues_;
  std::vector<std::string> warnings_;
  WarningTally tally_;  // every warn(), in full
};

}  // namespace lidarseg::logs
