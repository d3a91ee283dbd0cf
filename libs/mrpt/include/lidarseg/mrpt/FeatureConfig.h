#pragma once
/// @file FeatureConfig.h
/// Loading and saving the door and corner detector's parameters ([features] section).

#include <string>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>

#include "lidarseg/core/FeatureDetector.h"

namespace lidarseg::mrpt_adapter {

inline const std::string kFeaturesSection = "features";

/// Names of every key of the [features] section, in file order (the field names of
/// FeatureDetectorParams).
std::vector<std::string> featureKeys();

/// Reads the keys present in `section` into `params`, then validates them.
/// @throws std::invalid_argument naming source, section and key (unknown key, not a
/// number, out of range) or a missing section.
void loadFeatureDetectorParams(FeatureDetectorParams& params, const mrpt::config::CConfigFileBase& cfg,
                               const std::string& section = kFeaturesSection,
                               const std::string& source = "configuration");
/// Writes every key with full precision.
void saveFeatureDetectorParams(const FeatureDetectorParams& params, mrpt::config::CConfigFileBase& cfg,
                               const std::string& section = kFeaturesSection);
/// The [features] section of an INI (or YAML) file on top of the defaults; a file without
/// that section gives the defaults. Errors name file:line [features] key.
/// @throws std::runtime_error if the file cannot be read; std::invalid_argument as above.
FeatureDetectorParams loadFeatureDetectorParamsFile(const std::string& path);

}  // namespace lidarseg::mrpt_adapter
