#pragma once
/// @file
/// The regions of interest of a log's camera images (paper Fig. 7),
/// shared by lidarseg-features and the inspector.

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>

#include "lidarseg/core/Feature.h"
#include "lidarseg/vision/CameraModel.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::mrpt_adapter {

/// Projects a scan's features into a camera image of the same log.
class CameraRois {
 public:
  /// `log_path`: the rawlog (its `<name>_Images` directory holds externally stored images).
  /// `camera`: from the configuration; empty = each image's own calibration.
  CameraRois(std::string log_path, std::optional<vision::CameraParams> camera, const vision::RoiParams& rois);

  /// The boxes of `features` (frame of the lidar at `lidar_on_robot`) in `image`.
  /// @throws std::invalid_argument when the image's calibration is unusable.
  std::vector<vision::Roi> project(const mrpt::obs::CObservationImage& image, const mrpt::poses::CPose3D& lidar_on_robot,
                                   const std::vector<Feature>& features) const;

  /// The image's pixels (BGR), loaded from the images directory when stored externally.
  /// @throws std::runtime_error naming the file when it cannot be read, or the observation's
  /// label when an embedded image is outside vision::kMaxImageSidePx (the caller adds the
  /// log and entry).
  cv::Mat pixels(const mrpt::obs::CObservationImage& image) const;

  /// Name of the image's file (external storage), or "" when embedded in the log.
  static std::string fileOf(const mrpt::obs::CObservationImage& image);

 private:
  std::string images_dir_;
  std::optional<vision::CameraParams> camera_;
  vision::RoiParams rois_;
};

/// Draws the boxes (doors red, corners green) with their type names.
void drawRois(cv::Mat& bgr, const std::vector<vision::Roi>& rois);

/// `image,scan,t,file,feature,type,u_min,v_min,u_max,v_max,clipped`.
void writeRoiCsvHeader(std::ostream& os);
void writeRoiCsvRows(std::ostream& os, std::size_t image, std::size_t scan, double t, const std::string& file,
                     const std::vector<vision::Roi>& rois);

}  // namespace lidarseg::mrpt_adapter
