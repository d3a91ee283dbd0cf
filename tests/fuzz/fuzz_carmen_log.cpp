/// @file fuzz_carmen_log.cpp
/// libFuzzer target: any bytes read as a CARMEN log (plain or gzip), through lidarseg's
/// reader, the conversion to MRPT observations and core scans, and the segmentation.

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "FuzzInput.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/ScanConverter.h"

using namespace lidarseg;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeInput(data, size, "input.log");
  static const ScanSegmenter segmenter;
  try {
    mrpt_adapter::LaserLogReader reader(path);
    mrpt_adapter::ScanConverter converter;
    Segmentation segmentation;
    std::size_t n = 0;
    while (auto record = reader.next()) {
      fuzz::require(record->index == n, "scan indices are consecutive");
      fuzz::require(record->observation != nullptr, "a record holds an observation");
      fuzz::require(std::isfinite(record->stamp_s), "stamps are finite");
      ++n;
      try {  // as the apps do: a scan that cannot be converted is skipped with its place
        const Scan scan = converter.convert(*record->observation);
        segmenter.process(scan, segmentation);
      } catch (const std::invalid_argument&) {
      }
    }
    fuzz::require(reader.issues().size() <= reader.skipped(), "issues listed <= lines skipped");
  } catch (const std::runtime_error& e) {
    fuzz::requireNamed(e, path);
  } catch (const std::invalid_argument& e) {
    fuzz::requireNamed(e, path);
  }
  return 0;
}
