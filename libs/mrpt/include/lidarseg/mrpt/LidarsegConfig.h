#pragma once
/// @file LidarsegConfig.h
/// Every section a lidarseg tool reads, loaded once from one INI or YAML file.

#include <string>
#include <vector>

#include <mrpt/slam/CICP.h>

#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/SegmentOdometry.h"
#include "lidarseg/core/StampPolicy.h"
#include "lidarseg/mrpt/VisionConfig.h"

namespace lidarseg::mrpt_adapter {

/// The whole configuration of a run. Every section is optional (absent sections keep the
/// defaults); present ones are strict: unknown keys, values that are not numbers or out of
/// range, and unknown sections are errors naming file:line [section] key.
struct LidarsegConfig {
  /// [segmentation], [matcher], [refiner], [search], [odometry].
  OdometryParams odometry;
  /// [stamps]: how a log's stamps are repaired and odometry jumps told.
  StampPolicyParams stamps;
  /// [features]: doors and corners.
  FeatureDetectorParams features;
  /// [camera], [rois], [people].
  VisionConfig vision;
  /// [icp]: MRPT's ICP, the baseline (CICP's own keys, read by CICP from the same file, so
  /// YAML works as INI does). Starts from baselineIcpDefaults(), not MRPT's defaults; the
  /// section's keys replace those values one by one.
  mrpt::slam::CICP::TConfigParams icp = baselineIcpDefaults();

  /// The baseline ICP as configured without any [icp] key (decision 110): MRPT's defaults
  /// except every point paired (corresponding_points_decimation 1, MRPT's 5), a 0.5 m
  /// initial pairing threshold (thresholdDist, MRPT's 0.75 m) and up to 60 iterations
  /// (maxIterations, MRPT's 40): the configuration measured as the most accurate on the real
  /// logs (docs/results.md, decision 36), so that a run without a config file compares
  /// lidarseg with ICP configured for accuracy, as config/default.ini does.
  static mrpt::slam::CICP::TConfigParams baselineIcpDefaults();

  /// Reads `path` once. @throws std::runtime_error if it cannot be read;
  /// std::invalid_argument naming file:line [section] key.
  static LidarsegConfig loadFile(const std::string& path);
  /// The sections a lidarseg configuration may hold (those of every tool, including
  /// [simulation]).
  static const std::vector<std::string>& knownSections();
};

}  // namespace lidarseg::mrpt_adapter
