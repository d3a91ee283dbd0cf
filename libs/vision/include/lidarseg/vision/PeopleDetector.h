#pragma once
/// @file PeopleDetector.h
/// Pedestrian detection restricted to the regions of interest given by the lidar (beyond
/// the paper: its §V future work), with OpenCV's HOG people detector and its built-in
/// coefficients (Dalal-Triggs, 64 x 128 window).

#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/objdetect.hpp>

namespace lidarseg::vision {

/// Parameters of the HOG detector and of the crops taken around the regions of interest.
struct PeopleDetectorParams {
  /// SVM score above which a window is a person (OpenCV's hitThreshold).
  double hit_threshold = 0.0;
  /// Window stride (pixels, both axes); a multiple of the 8-pixel block stride.
  int win_stride_px = 8;
  /// Ratio between two levels of the image pyramid (> 1).
  double scale_step = 1.05;
  /// Minimum number of overlapping windows to keep a detection (OpenCV's groupThreshold).
  int group_threshold = 2;
  /// Each region is grown by this fraction of its size on every side before it is analysed,
  /// so a person standing across its border is still seen whole. At most 10.
  double roi_margin = 0.25;
  /// The image is resized by this factor before detection (people smaller than the 128-pixel
  /// window are found only with a factor > 1); boxes are returned in the original image.
  double image_scale = 1.0;

  /// @throws std::invalid_argument naming the key.
  void validate() const;
};

/// A person found in the image (pixels of the input image).
struct Person {
  cv::Rect box;
  double score = 0.0;  ///< SVM margin of the grouped detection
};

/// What one detection pass did.
struct PeopleDetection {
  std::vector<Person> people;
  /// Image regions the detector ran on (the whole image, or the grown, merged regions).
  std::vector<cv::Rect> analysed;
  /// Share of the image's pixels analysed (0..1).
  double analysed_fraction = 0.0;
};

/// HOG people detector on a whole image or only inside regions of interest.
class PeopleDetector {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit PeopleDetector(const PeopleDetectorParams& params = {});

  /// The whole image (BGR or grey).
  PeopleDetection detectFullFrame(const cv::Mat& image) const;

  /// Only inside the regions: each is grown by roi_margin, enlarged to at least one
  /// detection window, clipped to the image; overlapping regions are merged so that no
  /// pixel is analysed twice. Regions outside the image are ignored.
  PeopleDetection detectInRegions(const cv::Mat& image, const std::vector<cv::Rect>& regions) const;

  /// The regions detectInRegions() analyses for these ROIs in an image of this size.
  std::vector<cv::Rect> analysedRegions(const std::vector<cv::Rect>& regions, const cv::Size& image) const;

  const PeopleDetectorParams& params() const { return params_; }

 private:
  std::vector<Person> detect(const cv::Mat& image) const;

  PeopleDetectorParams params_;
  cv::HOGDescriptor hog_;
};

/// Merges overlapping rectangles into their bounding boxes until no two overlap.
std::vector<cv::Rect> mergeOverlapping(std::vector<cv::Rect> boxes);

/// Whether the centre of `box` (pixels, integer division) lies inside one of `regions`.
bool centredIn(const cv::Rect& box, const std::vector<cv::Rect>& regions);

/// Whether `box` overlaps one of `people`'s boxes with an intersection over union of at
/// least `iou` (0..1).
bool overlapsAny(const cv::Rect& box, const std::vector<Person>& people, double iou);

}  // namespace lidarseg::vision
