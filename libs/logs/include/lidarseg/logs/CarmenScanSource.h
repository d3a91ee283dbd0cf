#pragma once
/// @file CarmenScanSource.h
/// A CARMEN log (FLASER, RLASER, ROBOTLASER1 lines) as a ScanSource, with no MRPT in
/// between: each laser line's ranges become a core Scan on a centred beam layout, its
/// odometry the last ODOM line's (else the line's own fields) and its log pose the robot
/// pose the line gives (the corrected pose in Radish "corrected" logs).

#include <memory>
#include <string>
#include <vector>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/logs/ScanSource.h"

namespace lidarseg::logs {

class CarmenScanSource final : public ScanSource {
 public:
  /// Opens `path` (plain or gzip; a pipe is read once). `laser_type`: FLASER, RLASER or
  /// ROBOTLASER1; empty = the first laser line that parses.
  /// @throws std::runtime_error naming the file when it cannot be opened;
  /// std::invalid_argument when `laser_type` is no CARMEN laser type.
  CarmenScanSource(const std::string& path, const std::string& laser_type);

  std::string sensor() const override { return reader_.laserType(); }
  double fractionRead() const override { return reader_.fractionRead(); }
  std::vector<std::string> unknownTypes() const override;
  /// The laser lines of types the CARMEN reader does not read (RAWLASER1 ...), counted.
  std::string unreadScans() const override;

 protected:
  std::optional<ScanRecord> read() override;

 private:
  CarmenLogReader reader_;
  CentredLayoutCache layouts_;  // the lines' beam layouts
};

}  // namespace lidarseg::logs
