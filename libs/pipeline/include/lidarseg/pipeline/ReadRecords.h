#pragma once
/// @file ReadRecords.h
/// lidarseg::pipeline: how every tool reads its log: the records of a LaserLogReader
/// (numbers checked, bad lines and scans skipped with their place) handed one by one to the
/// tool's use of its report::RecordGate, with progress, then the reader's skips and warnings
/// added to the run's counts.

#include <cstddef>
#include <functional>
#include <string>

#include "lidarseg/report/RecordGate.h"

namespace lidarseg::mrpt_adapter {
class LaserLogReader;
struct LaserRecord;
}  // namespace lidarseg::mrpt_adapter

namespace lidarseg::pipeline {

using report::RecordCounts;

/// How a tool reads its log.
struct ReadSettings {
  /// The tool's name, for the progress line.
  std::string tool;
  /// The sensor asked for (empty: the first met), named when the log has no usable scan.
  std::string sensor;
  /// Stop after this many records used (0: all).
  std::size_t max_scans = 0;
  /// Progress with rate and ETA on stderr (only when stderr is a terminal).
  bool progress = true;
  /// A log that ends in a truncated or corrupt entry: false = the reader's error; true =
  /// the records before it stand, and the error is returned.
  bool allow_truncated = false;
};

/// Reads `reader` to its end (or `max_scans` records used): each record to `use`, which
/// runs it through the tool's gate and so moves `counts`. With `companions`, every record
/// read goes to it first, the one after the last used too (for the observations logged
/// before it: a camera image after the last scan).
/// @returns the error that ended the log early (allow_truncated), else "".
/// @throws the reader's errors; std::runtime_error naming the log, the sensor and the
/// first records skipped when no record was used.
std::string readRecords(mrpt_adapter::LaserLogReader& reader, const report::RecordCounts& counts, const ReadSettings& settings,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& use,
                        const std::function<void(const mrpt_adapter::LaserRecord&)>& companions = {});

/// The reader's side of the counts, after the run's: the lines and scans it skipped (the
/// list up to 100, the count in full), then its unknown line types and warnings.
void addReaderCounts(const mrpt_adapter::LaserLogReader& reader, report::RecordCounts& counts);

}  // namespace lidarseg::pipeline
