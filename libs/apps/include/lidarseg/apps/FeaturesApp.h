#pragma once
/// @file FeaturesApp.h
/// The logic of `lidarseg-features`: doors and corners in every scan of a laser log
/// (paper §III.B), written to a CSV file and, against a simulator's ground truth, scored.

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>

#include "lidarseg/report/FeaturesReport.h"

namespace lidarseg::apps {

/// Command-line options of `lidarseg-features`.
struct FeaturesOptions {
  /// Laser log: MRPT .rawlog or CARMEN.
  std::string input;
  /// INI/YAML file with [segmentation] and [features] sections (each optional).
  std::string config_path;
  /// Laser to use when the log has several (rawlog label or CARMEN line type).
  std::string sensor_label;
  std::size_t max_scans = 0;  ///< 0: all
  /// Per-scan features: `t,type,x,y,theta,width,confidence` (robot frame) then
  /// `scan,var_x,var_y,cov_xy,var_theta,var_width`.
  std::string out_csv;
  /// Ground truth `<prefix>.features.csv` from lidarseg-simulate: score the detections.
  std::string truth_path;
  /// With a truth: every true feature and every detection of every scan with what it was
  /// matched to, for scoring by bins (tests/benchmarks/buildings.py): CSV
  /// `scan,role,type,seen_as,x,y,theta,width,id,resolvable,match` (role truth: match = the
  /// detected type or none; role detection: id = the matched truth's id or -1, match = its
  /// seen_as or none; sensor frame, m and rad).
  std::string matches_out;
  /// Match gate for the score (m).
  double gate_m = 0.2;
  /// Whether --gate was given (it needs --gt: the gate scores against the truth).
  bool gate_given = false;
  /// Directory for features.md and features.json (the report).
  std::string report_dir;
  /// Picture of one scan (paper Fig. 6): raw points beside segments, doors (red) and
  /// corners (green). Scan index and PNG path.
  std::optional<std::size_t> figure_scan;
  std::string figure_path;
  /// Regions of interest of every camera image of the log (paper Fig. 7): the features of
  /// the scan just before the image projected with the [camera] section of the
  /// configuration, or with the image's own calibration when there is none. CSV
  /// `image,scan,t,file,feature,type,u_min,v_min,u_max,v_max,clipped` (pixels, inclusive).
  std::string rois_out;
  /// Directory for the camera images with their ROI boxes drawn (doors red, corners green).
  std::string images_out;
  /// Progress with rate and ETA on stderr (shown only when stderr is a terminal; -q: off).
  bool progress = true;
};

/// Everything `lidarseg-features` measured (lidarseg::pipeline's, with its writers).
using FeaturesReport = report::FeaturesReport;

/// Runs the door and corner detector over a whole log.
class FeaturesApp {
 public:
  explicit FeaturesApp(FeaturesOptions options);

  /// @throws std::runtime_error / std::invalid_argument naming the file and line or key
  /// for an unreadable log, configuration or ground truth.
  FeaturesReport run();

  /// The report as Markdown (report::featuresMarkdown) on `os` (the results: stdout).
  static void print(const FeaturesReport& report, std::ostream& os);
  /// The run's warnings on `err` (stderr), after the results: one line per kind of the log's
  /// warnings (time gaps, clock jumps, ...) with its count and first place, as
  /// lidarseg-odometry prints them; each warning of the run; then the skipped scans and
  /// images counted with the first in full. Nothing when there is none.
  static void printWarnings(const FeaturesReport& report, std::ostream& err);

 private:
  FeaturesOptions options_;
};

}  // namespace lidarseg::apps
