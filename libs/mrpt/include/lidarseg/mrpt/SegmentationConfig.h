#pragma once
/// @file SegmentationConfig.h
/// Loading and saving lidarseg::SegmentationParams with MRPT's configuration files.

#include <string>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>

#include "lidarseg/core/ScanSegmenter.h"

namespace lidarseg::mrpt_adapter {

/// Default section of the segmentation parameters in INI/YAML files.
inline const std::string kSegmentationSection = "segmentation";

/// Names of every key of the segmentation section, in file order.
std::vector<std::string> segmentationKeys();

/// Reads the keys present in `section` of `cfg` into `params` (absent keys keep their
/// value), then validates the result. Works for INI files and for YAML loaded with
/// `CConfigFileBase::setContentFromYAML` (top-level key = section).
/// @param source a name for error messages (usually the file's path).
/// @throws std::invalid_argument naming source, section and key for an unknown key, a
/// value that is not a number, or a value out of range.
void loadSegmentationParams(SegmentationParams& params, const mrpt::config::CConfigFileBase& cfg,
                            const std::string& section = kSegmentationSection,
                            const std::string& source = "configuration");

/// Writes every key of `params` into `section` of `cfg`, with full precision.
void saveSegmentationParams(const SegmentationParams& params, mrpt::config::CConfigFileBase& cfg,
                            const std::string& section = kSegmentationSection);

/// Loads a configuration file: YAML when its name ends in .yaml or .yml, INI otherwise.
/// Returns the parameters of `section` on top of the defaults.
/// @throws std::runtime_error if the file cannot be read; std::invalid_argument as above.
SegmentationParams loadSegmentationParamsFile(const std::string& path,
                                              const std::string& section = kSegmentationSection);

}  // namespace lidarseg::mrpt_adapter
