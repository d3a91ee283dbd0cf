#include "lidarseg/mrpt/VisionConfig.h"

#include <stdexcept>

#include <mrpt/math/CMatrixFixed.h>

#include "ConfigKeys.h"
#include "KeyTables.h"
#include "SectionLoaders.h"

namespace lidarseg::mrpt_adapter {

std::vector<std::string> cameraKeys() { return detail::keysOf<vision::CameraParams>(detail::CameraKeys{}); }
std::vector<std::string> roiKeys() { return detail::keysOf<vision::RoiParams>(detail::RoiKeys{}); }
std::vector<std::string> peopleKeys() { return detail::keysOf<vision::PeopleDetectorParams>(detail::PeopleKeys{}); }

namespace detail {
void loadVisionSections(VisionConfig& out, const LoadedConfig& file, const std::string& path) {
  if (file.cfg.sectionExists(kCameraSection)) {
    vision::CameraParams camera;
    loadKeys(camera, file.cfg, kCameraSection, path, file.linesOf(kCameraSection), CameraKeys{});
    out.camera = camera;
  }
  if (file.cfg.sectionExists(kRoisSection)) {
    loadKeys(out.rois, file.cfg, kRoisSection, path, file.linesOf(kRoisSection), RoiKeys{});
  }
  if (file.cfg.sectionExists(kPeopleSection)) {
    loadKeys(out.people, file.cfg, kPeopleSection, path, file.linesOf(kPeopleSection), PeopleKeys{});
  }
}
}  // namespace detail

VisionConfig loadVisionConfigFile(const std::string& path) {
  VisionConfig out;
  detail::loadVisionSections(out, detail::readConfigFile(path), path);
  return out;
}

void saveVisionConfig(const VisionConfig& config, mrpt::config::CConfigFileBase& cfg) {
  if (config.camera) detail::saveKeys(*config.camera, cfg, kCameraSection, detail::CameraKeys{});
  detail::saveKeys(config.rois, cfg, kRoisSection, detail::RoiKeys{});
  detail::saveKeys(config.people, cfg, kPeopleSection, detail::PeopleKeys{});
}

vision::CameraModel cameraOf(const mrpt::obs::CObservationImage& image, const mrpt::poses::CPose3D& lidar_on_robot) {
  const auto& c = image.cameraParams;
  vision::CameraParams p;
  p.width = static_cast<int>(c.ncols);
  p.height = static_cast<int>(c.nrows);
  p.fx = c.fx();
  p.fy = c.fy();
  p.cx = c.cx();
  p.cy = c.cy();
  p.k1 = c.k1();
  p.k2 = c.k2();
  p.p1 = c.p1();
  p.p2 = c.p2();
  p.k3 = c.k3();
  // The lidar's pose seen from the camera: lidar-frame points to camera-frame points.
  const mrpt::poses::CPose3D camera_from_lidar = lidar_on_robot - image.cameraPose;
  const mrpt::math::CMatrixDouble44 H = camera_from_lidar.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  Eigen::Matrix4d T;
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) T(r, k) = H(r, k);
  }
  try {
    return vision::CameraModel(p, T);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("camera '" + image.sensorLabel + "': " + e.what());
  }
}

}  // namespace lidarseg::mrpt_adapter
