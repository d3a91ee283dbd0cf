#pragma once
/// @file PeopleComparison.h
/// The people detector run on each camera frame twice, on the whole frame and only inside
/// the regions of interest, both timed and compared (what `lidarseg-people` measures;
/// beyond the paper: its §V future work).

#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/vision/PeopleDetector.h"

namespace lidarseg::vision {

/// Everything `lidarseg-people` measured.
struct PeopleReport {
  std::string input;
  std::size_t frames = 0;  ///< analysed
  /// Frames of the input skipped because they could not be decoded (a corrupt Motion-JPEG
  /// frame, a folder's unreadable or oversized image), and the first of them with their place
  /// in `warnings` ("'VIDEO', frame N: why; frame skipped", "'IMAGE': why; image skipped").
  std::size_t frames_skipped = 0;
  std::vector<std::string> warnings;
  cv::Size frame_size;
  /// Time per frame of the detector (ms): whole frame and inside the regions.
  Summary full_ms;
  Summary rois_ms;
  /// Per frame: share of the image analysed inside the regions (0..1), and time inside the
  /// regions over time on the whole frame.
  Summary analysed_fraction;
  Summary time_ratio;
  std::size_t people_full = 0;            ///< detections on the whole frames
  std::size_t people_in_regions = 0;      ///< of those, centred inside a region
  std::size_t people_still_found = 0;     ///< of those, found by the detection inside the regions
  std::size_t people_rois = 0;            ///< detections inside the regions
  std::size_t people_rois_confirmed = 0;  ///< of those, overlapping a whole-frame detection
  /// Regions that lie wholly outside their frame (nothing of the frame analysed for them:
  /// a `--roi` or a regions file made for another camera or image size), and the first of
  /// them ("frame N: region u_min,v_min,u_max,v_max outside the W x H frame").
  std::size_t regions_outside = 0;
  std::string first_region_outside;
  /// Frames analysed with at least one region: 0 when the regions name no frame or image of
  /// the input (a regions file of another video), which the run then says.
  std::size_t frames_with_regions = 0;

  /// people_still_found / people_in_regions; NaN when no person was centred in a region.
  double recallInRegions() const;
};

/// Runs the detector both ways on each frame and fills a PeopleReport.
class PeopleComparison {
 public:
  /// The two detections of one frame.
  struct FrameDetections {
    PeopleDetection full;    ///< on the whole frame
    PeopleDetection inside;  ///< inside the regions
  };

  /// `match_iou`: least intersection over union for two detections to be the same person.
  PeopleComparison(const PeopleDetector& detector, double match_iou, PeopleReport& report);

  /// One frame (BGR) with its regions (pixels): both detections timed (wall clock, ms),
  /// counted and compared; the frame counted in the report.
  FrameDetections add(const cv::Mat& frame, const std::vector<cv::Rect>& rois);

  /// The per-frame samples summarised into the report (times, analysed share, time ratio).
  void summarise() const;

 private:
  // Whole-frame people centred in a region and found again inside the regions; detections
  // inside the regions that the whole frame also has.
  void countPeople(const std::vector<Person>& full, const std::vector<Person>& inside,
                   const std::vector<cv::Rect>& rois);

  const PeopleDetector& detector_;
  double match_iou_;
  PeopleReport& report_;
  std::vector<double> full_ms_, rois_ms_, fraction_, ratio_;
};

}  // namespace lidarseg::vision
