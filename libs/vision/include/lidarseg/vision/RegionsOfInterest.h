#pragma once
/// @file RegionsOfInterest.h
/// Doors and corners of the lidar projected into the camera image as boxes (paper §III.B,
/// Fig. 7), and detection restricted to them.

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "lidarseg/core/Feature.h"
#include "lidarseg/vision/CameraModel.h"

namespace lidarseg::vision {

/// How a feature becomes a 3D box in the lidar frame (m).
struct RoiParams {
  /// Height of the lidar above the floor: boxes start at the floor.
  double lidar_height_m = 0.3;
  /// A door: from the floor to this height, between its jambs.
  double door_height_m = 2.0;
  /// A corner: a vertical strip this wide, centred on it, across the line of sight, from
  /// the floor to this height (where a person would appear).
  double corner_strip_m = 0.8;
  double corner_height_m = 2.0;
  /// Boxes smaller than this (pixels, either side) after clipping are dropped.
  int min_size_px = 4;

  /// @throws std::invalid_argument naming the key.
  void validate() const;
};

/// A region of interest: a feature's box in the image.
struct Roi {
  std::size_t feature = 0;  ///< index in the features given
  FeatureType type = FeatureType::kDoorOpen;
  cv::Rect box;             ///< clipped to the image (pixels)
  bool clipped = false;     ///< part of the 3D box lay outside the image or behind the camera
};

/// Projects features of the lidar frame into the image: each 3D box is clipped against the
/// camera's near plane (points behind the camera are never projected), its corners are
/// projected with the camera's K and distortion, and the bounding box is clipped to the image.
class RoiProjector {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  RoiProjector(CameraModel camera, const RoiParams& params = {});

  std::vector<Roi> project(const std::vector<Feature>& features) const;

  const CameraModel& camera() const { return camera_; }
  const RoiParams& params() const { return params_; }

 private:
  /// Box of the vertical quad between lidar-frame points a and b (x, y), from z0 to z1.
  bool boxOfQuad(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z0, double z1, cv::Rect& box,
                 bool& clipped) const;

  CameraModel camera_;
  RoiParams params_;
};

/// Intersection over union of two boxes (0 when disjoint).
double intersectionOverUnion(const cv::Rect& a, const cv::Rect& b);

/// Grows a box by `margin` (fraction of its size on each side) and clips it to the image.
cv::Rect grow(const cv::Rect& box, double margin, const cv::Size& image);

/// Share of the image covered by the union of the boxes (0..1).
double coveredFraction(const std::vector<cv::Rect>& boxes, const cv::Size& image);

}  // namespace lidarseg::vision
