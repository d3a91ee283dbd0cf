#pragma once
// Private to lidarseg::mrpt: each group of sections loaded from a configuration file read
// once (errors name file:line [section] key). The public *File() loaders and
// LidarsegConfig::loadFile() share them.

#include <string>

#include "ConfigKeys.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/VisionConfig.h"

namespace lidarseg::mrpt_adapter::detail {

/// [segmentation], [matcher], [refiner], [search], [odometry], each when present.
void loadOdometrySections(OdometryParams& params, const LoadedConfig& file, const std::string& source);
/// [features] when present.
void loadFeatureSection(FeatureDetectorParams& params, const LoadedConfig& file, const std::string& source);
/// [camera], [rois], [people], each when present.
void loadVisionSections(VisionConfig& config, const LoadedConfig& file, const std::string& source);
/// [stamps] when present.
void loadStampSection(StampPolicyParams& params, const LoadedConfig& file, const std::string& source);

}  // namespace lidarseg::mrpt_adapter::detail
