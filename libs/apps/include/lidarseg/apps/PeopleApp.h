#pragma once
/// @file PeopleApp.h
/// The logic of `lidarseg-people`: OpenCV's HOG people detector on every frame of a video or
/// image sequence, once on the whole frame and once only inside regions of interest, timed
/// and compared (beyond the paper: its §V future work).

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "lidarseg/vision/PeopleComparison.h"

namespace lidarseg::apps {

/// Command-line options of `lidarseg-people`.
struct PeopleOptions {
  /// A video file (anything OpenCV's VideoCapture reads), a directory of images (read in
  /// name order), or one image.
  std::string input;
  /// Regions per frame: CSV with a header naming u_min,v_min,u_max,v_max (pixels,
  /// inclusive) and the frame as `frame` or `image` (0-based index; -1 or * = every frame)
  /// or `file` (image file name). lidarseg-features --rois-out writes such a file.
  std::string rois_path;
  /// Regions for every frame, "u_min,v_min,u_max,v_max" each.
  std::vector<std::string> rois;
  /// INI/YAML file with a [people] section (optional).
  std::string config_path;
  std::size_t max_frames = 0;  ///< 0: all
  std::size_t every = 1;       ///< analyse every N-th frame
  /// OpenCV worker threads (1 gives per-frame costs that compare across runs).
  int threads = 1;
  /// A detection found on the whole frame is "inside the regions" when its centre lies in
  /// one (before the margin); it is "still found" when a detection inside the regions
  /// overlaps it with at least this IoU.
  double match_iou = 0.5;
  /// Detections `frame,mode,u_min,v_min,u_max,v_max,score` (mode: full or rois).
  std::string out_csv;
  /// Directory for people.md and people.json.
  std::string report_dir;
  /// Directory for annotated frames (regions yellow, analysed crops grey, whole-frame
  /// detections blue, detections inside the regions red), every `draw_every` analysed frame.
  std::string draw_dir;
  std::size_t draw_every = 50;
  /// Progress with rate and ETA on stderr (shown only when stderr is a terminal; -q: off).
  bool progress = true;
};

/// Everything `lidarseg-people` measured (lidarseg::vision's).
using PeopleReport = vision::PeopleReport;

class PeopleApp {
 public:
  /// @throws std::invalid_argument for bad options (naming the option and value).
  explicit PeopleApp(PeopleOptions options);

  /// @throws std::runtime_error naming the file (and line) for unreadable input or regions.
  PeopleReport run();

  static std::string markdown(const PeopleReport& report);
  static void print(const PeopleReport& report, std::ostream& os);
  /// The frames skipped as undecodable, on `err` (stderr): how many, and the first with its
  /// place; nothing when none was.
  static void printWarnings(const PeopleReport& report, std::ostream& err);

 private:
  PeopleOptions options_;
};

}  // namespace lidarseg::apps
