/// @file fuzz_carmen_log.cpp
/// libFuzzer target: any bytes read as a CARMEN log (plain or gzip), through lidarseg's
/// reader, the conversion to MRPT observations and core scans, and the segmentation.

#include <cstdint>

#include "LogThroughCore.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lidarseg::fuzz::readLogThroughCore(lidarseg::fuzz::writeInput(data, size, "input.log"));
  return 0;
}
