#pragma once
/// @file OdometryConfig.h
/// Loading and saving the matcher and odometry parameters with MRPT's configuration files.

#include <string>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>

#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/SegmentationConfig.h"

namespace lidarseg::mrpt_adapter {

inline const std::string kMatcherSection = "matcher";
inline const std::string kOdometrySection = "odometry";
inline const std::string kRefinerSection = "refiner";
inline const std::string kSearchSection = "search";
inline const std::string kStampsSection = "stamps";

/// Names of every key of the [matcher] and [odometry] sections, in file order.
std::vector<std::string> matcherKeys();
std::vector<std::string> odometryKeys();
/// Names of every key of the [refiner] and [search] sections.
std::vector<std::string> refinerKeys();
std::vector<std::string> searchKeys();
/// Names of every key of the [stamps] section (lidarseg::StampPolicyParams).
std::vector<std::string> stampKeys();

/// Reads [segmentation], [matcher], [refiner], [search] and [odometry], each when present (absent sections
/// keep the defaults: a file may hold only some of them), and validates.
/// @throws std::invalid_argument as above.
void loadOdometryParams(OdometryParams& params, const mrpt::config::CConfigFileBase& cfg,
                        const std::string& source = "configuration");
/// Writes the five sections with every key.
void saveOdometryParams(const OdometryParams& params, mrpt::config::CConfigFileBase& cfg);

/// Writes the [stamps] section with every key.
void saveStampPolicyParams(const StampPolicyParams& params, mrpt::config::CConfigFileBase& cfg);

/// Loads an INI (or YAML, by extension) file's five sections on top of the defaults,
/// with errors naming file:line [section] key.
/// @throws std::runtime_error if the file cannot be read; std::invalid_argument as above.
OdometryParams loadOdometryParamsFile(const std::string& path);

}  // namespace lidarseg::mrpt_adapter
