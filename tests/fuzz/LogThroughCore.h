#pragma once
/// @file LogThroughCore.h
/// The path a laser log takes in the apps, for the log fuzz targets: LaserLogReader (either
/// format), the conversion to core scans and the segmentation.

#include <cmath>
#include <stdexcept>
#include <string>

#include "FuzzInput.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/ScanConverter.h"

namespace lidarseg::fuzz {

/// Reads the log at `path` to its end through the core. Checks: consecutive indices, an
/// scan per record (and an MRPT observation of it), finite stamps, no more issues listed than lines skipped, and
/// errors that name the file.
inline void readLogThroughCore(const std::string& path) {
  static const ScanSegmenter segmenter;
  expectNamedErrors(path, [&] {
    mrpt_adapter::LaserLogReader reader(path);
    mrpt_adapter::ScanConverter converter;
    Segmentation segmentation;
    std::size_t n = 0;
    while (auto record = reader.next()) {
      require(record->index == n, "scan indices are consecutive");
      require(record->scan.size() >= 2 && record->scan.layout != nullptr, "a record holds a scan");
      require(std::isfinite(record->stamp_s), "stamps are finite");
      ++n;
      try {  // as the apps do: a scan that cannot be converted is skipped with its place
        segmenter.process(record->scan, segmentation);
        const Scan scan = converter.convert(*mrpt_adapter::observationOf(*record));  // what ICP reads
        require(scan.size() == record->scan.size(), "the observation has the record's beams");
      } catch (const std::invalid_argument&) {
      }
    }
    require(reader.issues().size() <= reader.skipped(), "issues listed <= lines skipped");
  });
}

}  // namespace lidarseg::fuzz
