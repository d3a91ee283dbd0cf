#pragma once
/// @file InspectApp.h
/// The logic of `lidarseg-inspect`: a RawLogViewer-style inspector of what lidarseg's
/// pipeline sees, scan by scan (segments of every cascade level, the match against the
/// keyframe, doors and corners, trajectories, the camera with its regions of interest):
/// an MRPT window, a headless renderer (PNG/SVG) and a static HTML report.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/inspect/LogReport.h"
#include "lidarseg/inspect/Session.h"

namespace lidarseg::apps {

/// Command-line options of `lidarseg-inspect`.
struct InspectOptions {
  std::string input;         ///< rawlog or CARMEN log
  std::string config_path;   ///< INI/YAML: [segmentation] [matcher] [odometry] [features] [camera] [rois]
  std::string sensor_label;
  /// Trajectories to show beside lidarseg's: "NAME=FILE.tum" (e.g. icp=run/icp.tum).
  std::vector<std::string> references;
  /// Ground truth TUM file; by default `<log>.gt.tum` beside a simulated log when present.
  std::string truth_path;
  std::size_t frame = 0;                ///< scan to open at
  std::optional<double> time_s;         ///< or the scan nearest this time (s from the first scan)
  /// Layers: comma list of raw,l0,l1,l2,l3,indices,predicted,matches,features,trajectory,camera
  /// (empty: the defaults).
  std::string layers;
  int width = 1100, height = 850;       ///< picture size (pixels)
  /// Headless: draw `frame` to this file (.png or .svg) and exit.
  std::string render_out;
  /// Window: show `frame`, save a screenshot of the window to this PNG and exit.
  std::string screenshot_out;
  /// Static HTML report of the whole log (index.html and images) in this directory.
  std::string report_dir;
  std::size_t gallery = 12;             ///< frames in the report's gallery
  /// Where the window's "save parameters" key writes the INI file.
  std::string save_path = "lidarseg-inspect.ini";
  /// Window: print "shown scan N" on stdout each time a picture is shown (after every key),
  /// so that a script driving the window can wait on its state rather than on time.
  bool trace = false;
  /// Progress of --out/--report with rate and ETA on stderr (only on a terminal; -q: off).
  bool progress = true;
};

/// What `--report` measured (also written into index.html).
using InspectReport = inspect::ReportSummary;

class InspectApp {
 public:
  /// @throws std::invalid_argument for bad options (naming the option).
  explicit InspectApp(InspectOptions options);

  /// Runs the mode the options ask for: render, report, screenshot or the interactive
  /// window. Returns the process exit code.
  /// @throws std::runtime_error naming the file (and line/scan) for unreadable input.
  int run();

  /// The keyboard shortcuts of the window, one per line.
  static std::vector<std::string> keyHelp();

  /// Writes the HTML report of the whole log (inspect::writeLogReport), with a warning on
  /// stderr when it has no plots; used by run().
  InspectReport writeReport(inspect::Session& session);

  /// The log's session with its references: the ground truth (--gt, or PREFIX.gt.tum found
  /// beside the log as lidarseg-odometry finds it, report::groundTruthBeside) and the
  /// --trajectory files; used by run().
  /// @throws std::runtime_error naming the file for an unreadable log or reference.
  std::unique_ptr<inspect::Session> open();

 private:
  // The scan nearest `t_s` seconds after the first; an error for a negative or non-finite
  // time, or one more than a second past the last scan.
  std::size_t scanAtTime(inspect::Session& session, double t_s);
  // Draws options_.frame headless to options_.render_out (PNG or SVG).
  void render(inspect::Session& session);
  // The interactive window (or its screenshot); never returns: the process leaves from it
  // after calling `release` (the run's claims on its outputs).
  int window(inspect::Session& session, const std::function<void()>& release);

  InspectOptions options_;
  std::string truth_path_;  ///< the ground truth read (given, or found beside the log); empty without one
};

}  // namespace lidarseg::apps
