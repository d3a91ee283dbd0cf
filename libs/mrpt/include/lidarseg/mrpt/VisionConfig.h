#pragma once
/// @file VisionConfig.h
/// The camera side's parameters in configuration files ([camera], [rois], [people]) and the
/// camera of an MRPT image observation.

#include <optional>
#include <string>
#include <vector>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose3D.h>

#include "lidarseg/vision/CameraModel.h"
#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::mrpt_adapter {

inline const std::string kCameraSection = "camera";
inline const std::string kRoisSection = "rois";
inline const std::string kPeopleSection = "people";

/// Names of the keys of each section, in file order (the fields of CameraParams,
/// RoiParams and PeopleDetectorParams).
std::vector<std::string> cameraKeys();
std::vector<std::string> roiKeys();
std::vector<std::string> peopleKeys();

/// What a configuration file says about the camera side. `camera` is empty when the file
/// has no [camera] section (the camera is then taken from the log's image observations).
struct VisionConfig {
  std::optional<vision::CameraParams> camera;
  vision::RoiParams rois;
  vision::PeopleDetectorParams people;
};

/// Reads [camera], [rois] and [people] (each optional; absent keys keep their defaults).
/// @throws std::runtime_error if the file cannot be read; std::invalid_argument naming
/// file:line [section] key for an unknown key, a value that is not a number or out of range.
VisionConfig loadVisionConfigFile(const std::string& path);

/// Writes the three sections with full precision (the camera only when set).
void saveVisionConfig(const VisionConfig& config, mrpt::config::CConfigFileBase& cfg);

/// The camera of an image observation seen from a lidar mounted at `lidar_on_robot`:
/// intrinsics, distortion and size from its cameraParams, and T_camera_lidar from its
/// cameraPose (MRPT's camera axes: z forward, x right, y down, on the robot).
/// @throws std::invalid_argument when the observation's calibration is unusable
/// (zero focal length or image size).
vision::CameraModel cameraOf(const mrpt::obs::CObservationImage& image, const mrpt::poses::CPose3D& lidar_on_robot);

}  // namespace lidarseg::mrpt_adapter
