#pragma once
/// @file RawlogScanSource.h
/// An MRPT rawlog (both layouts, plain or gzip) as a logs::ScanSource: each 2D range scan of
/// the chosen label becomes a core ScanRecord; the MRPT observation it came from and the
/// observations read since the previous scan are kept for the MRPT-side consumers (the ICP
/// baseline, the rawlog writer, the camera's regions of interest).

#include <memory>
#include <string>
#include <vector>

#include <mrpt/obs/CObservation2DRangeScan.h>

#include "lidarseg/logs/ScanSource.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::mrpt_adapter {

class RawlogScanReader;

class RawlogScanSource final : public logs::ScanSource {
 public:
  /// Opens the rawlog `path` (a regular file: MRPT's reader and the gzip end check open it
  /// more than once). `label`: the sensor label to read; empty = the first laser scan's.
  /// @throws std::runtime_error naming the file when it cannot be opened or is no regular file.
  RawlogScanSource(const std::string& path, const std::string& label);
  ~RawlogScanSource() override;

  std::string sensor() const override;
  double fractionRead() const override;

  /// The MRPT observation of the record next() returned last (laid out as the core scan:
  /// an upside-down laser's beams reversed, the sensor pose levelled).
  const mrpt::obs::CObservation2DRangeScan::Ptr& lastObservation() const { return observation_; }
  /// The observations read between the previous scan and the last one returned, moved out.
  std::vector<mrpt::obs::CObservation::Ptr> takeCompanions() { return std::move(companions_); }

 protected:
  std::optional<ScanRecord> read() override;
  std::vector<std::string> sourceWarnings() const override;
  WarningTally sourceWarningTally() const override;

 private:
  std::string droppedCompanionsMessage() const;
  std::unique_ptr<RawlogScanReader> reader_;
  ScanConverter converter_;  // observations to core scans (beam layouts cached)
  mrpt::obs::CObservation2DRangeScan::Ptr observation_;
  std::vector<mrpt::obs::CObservation::Ptr> companions_;
};

}  // namespace lidarseg::mrpt_adapter
