#pragma once
/// @file LogReport.h
/// The figures and the page of `lidarseg-inspect --report`: every scan of a log read
/// through the Session, compared with the ground truth when there is one, the worst scans
/// found for the gallery, and the static HTML page (no server, no script needed to read it;
/// one small script only checks that every image loaded). The pictures are the tool's.

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/inspect/Session.h"

namespace lidarseg::inspect {

/// What the report measured over the whole log (also written into index.html).
struct ReportSummary {
  std::size_t scans = 0;
  std::size_t failed_matches = 0;
  double length_m = 0.0;                ///< lidarseg's path length
  std::optional<double> final_error_m;  ///< against the ground truth (m)
  std::vector<std::size_t> gallery;     ///< frames drawn, worst first
  /// Why the report has no plots (gnuplot missing or failing); empty when it has them.
  std::string no_plots;
  /// Why a ground truth the session holds was left out (fewer than two scans have a pose
  /// of it within kTruthToleranceS: another log's truth); empty when it was used or absent.
  std::string truth_problem;
};

/// One scan's row of the report's tables.
struct ScanRow {
  std::size_t index = 0;
  double t = 0.0;                 ///< the scan's stamp (s)
  std::string status;             ///< the tracking status, and why the segment match failed
  bool failed = false;            ///< a scan after the first whose status is not ok
  std::size_t matches = 0;        ///< segment pairs of the match
  double sd_xy_m = 0.0;           ///< sqrt of the increment's position variances' sum
  double total_us = 0.0;          ///< W-D + cascade + matching (microseconds)
  std::size_t features = 0;       ///< doors and corners
  Pose2D pose;                    ///< lidarseg's laser pose (odometry frame)
  double error_m = std::nan("");  ///< |increment error| against the truth (m)
  double drift_m =
      std::nan("");  ///< position error against the truth, aligned at the first scan (m)
};

/// Largest difference between a scan's stamp and a ground-truth pose's for the two to be
/// compared (s).
inline constexpr double kTruthToleranceS = 0.02;

/// The ground truth among the session's references (named "ground truth"), nullptr without one.
const eval::StampedTrajectory* groundTruth(const Session& session);

/// Every scan's row, compared with `truth` (robot poses, moved to the laser by the first
/// scan's mounting) when given. Progress with rate and ETA on stderr when `show_progress`.
std::vector<ScanRow> scanRows(Session& session, const eval::StampedTrajectory* truth,
                              bool show_progress);

/// Scans, failed matches, path length and the final error against the truth; no gallery.
ReportSummary summarizeRows(const std::vector<ScanRow>& rows);

/// The `count` worst scans, worst first: failed matches, then the largest error against the
/// truth (or, without a truth, the largest uncertainty).
std::vector<std::size_t> worstFirst(const std::vector<ScanRow>& rows, std::size_t count);

/// index.html for the log `input`: the results table, trajectory.png, error_over_time.png,
/// timing.png, the gallery's table and its pictures frames/scan_N.png (the caller writes
/// the pictures beside it). `no_plots`: when not empty, why the three plots could not be
/// drawn (no gnuplot): the page says so instead of showing broken images.
std::string reportHtml(const std::string& input, const ReportSummary& summary,
                       const std::vector<ScanRow>& rows, bool with_truth, const std::string& no_plots = {});

/// The names of the files writeLogReport() writes in its folder (its gallery's pictures go in
/// `frames/`): what lidarseg-inspect's command line is checked against.
std::vector<std::string> reportFileNames();

/// How writeLogReport() writes the report.
struct ReportSettings {
  std::string dir;     ///< the report's folder (created)
  std::string input;   ///< the log, as the page names it
  /// The gallery's layers (comma list, parseLayers()); empty: raw, l1, l3, predicted,
  /// matches, features, trajectory and camera.
  std::string layers;
  std::size_t gallery = 12;  ///< frames in the gallery
  bool progress = true;      ///< progress of the rows on stderr (only on a terminal)
  std::string truth_path;    ///< the ground truth's file, as warnings name it
};

/// The whole --report of the session's log, put in place together: DIR/index.html
/// (reportHtml()), trajectory.png (lidarseg and every reference from its pose at the first
/// scan), error_over_time.png (the error against the truth, or the match's sd),
/// timing.png (time per scan) and the gallery's frames/scan_N.png (900 x 700). Without
/// gnuplot the plots are left out and the summary's `no_plots` says why. A ground truth
/// that pairs with fewer than two scans is left out and `truth_problem` says why.
/// @throws std::runtime_error when a file cannot be written.
ReportSummary writeLogReport(Session& session, const ReportSettings& settings);

}  // namespace lidarseg::inspect
