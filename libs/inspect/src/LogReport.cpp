#include "lidarseg/inspect/LogReport.h"

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <utility>

#include "lidarseg/core/Statistics.h"
#include "lidarseg/inspect/Drawing.h"
#include "lidarseg/inspect/LayerSwitches.h"
#include "lidarseg/report/Format.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Plots.h"
#include "lidarseg/report/Progress.h"
#include "lidarseg/report/RunEvaluation.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::inspect {

using report::escapeXml;
using report::fixed;
using report::makeSeries;
using report::plotHistogramsPng;
using report::plotTrajectoriesPng;
using report::plotXYPng;
using report::PlotSeries;

namespace fs = std::filesystem;

namespace {

// One scan's row of the table, without the columns against the truth.
ScanRow scanRow(const Frame& f, const Pose2D& pose) {
  ScanRow row;
  row.index = f.index;
  row.t = f.stamp_s;
  row.status = toString(f.step.status);
  if (f.step.match.status == MatchStatus::kTooFewMatches && !f.step.first) {
    row.status += std::string(" (segment match: ") + f.step.match.rejections.dominant() + ")";
  }
  row.failed = !f.step.first && f.step.status != TrackStatus::kOk;
  row.matches = f.step.match.matches.size();
  row.sd_xy_m = std::sqrt(
      std::max(0.0, f.step.increment_covariance(0, 0) + f.step.increment_covariance(1, 1)));
  row.total_us = f.step.wall_danielsson_us + f.step.cascade_us + f.step.matching_us;
  row.features = f.features.size();
  row.pose = pose;
  return row;
}

// Fills drift_m and error_m. The truth (robot poses) moved to the laser by its mounting,
// anchored at the first scan's time, is compared with lidarseg's laser poses (which start
// at the first scan).
void compareWithTruth(std::vector<ScanRow>& rows, const eval::StampedTrajectory& truth,
                      const Pose2D& mount) {
  const auto first = eval::nearestIndex(truth, rows.front().t, 1.0);
  if (!first) return;
  const Pose2D truth_origin = compose(truth[*first].pose, mount);
  Pose2D prev_truth;
  bool has_prev = false;  // whether prev_truth is the previous scan's
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto k = eval::nearestIndex(truth, rows[i].t, kTruthToleranceS);
    if (!k) {
      has_prev = false;
      continue;
    }
    const Pose2D g = compose(truth[*k].pose, mount);
    const Pose2D aligned = relative(g, truth_origin);  // truth in lidarseg's odometry frame
    rows[i].drift_m = std::hypot(aligned.x - rows[i].pose.x, aligned.y - rows[i].pose.y);
    if (has_prev && i > 0) {
      const Pose2D true_inc = relative(g, prev_truth);
      const Pose2D inc = relative(rows[i].pose, rows[i - 1].pose);
      rows[i].error_m = std::hypot(true_inc.x - inc.x, true_inc.y - inc.y);
    }
    prev_truth = g;
    has_prev = true;
  }
}

// The page's head, title and the log's name.
std::string htmlHeader(const std::string& input) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta "
          "charset=\"utf-8\"><title>lidarseg-inspect: "
       << escapeXml(fs::path(input).filename().string()) << "</title>\n"
       << "<style>body{font-family:sans-serif;margin:2em;max-width:1200px}table{border-collapse:"
          "collapse}"
          "td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}th{background:#eee}"
          "figure{display:inline-block;margin:6px}img{max-width:100%}figcaption{font-size:90%}</"
          "style>\n"
       << "</head><body>\n<h1>lidarseg-inspect report</h1>\n<p>Log: <code>" << escapeXml(input)
       << "</code></p>\n";
  return html.str();
}

// The results table and the three plots (or, when they could not be drawn, why).
std::string htmlResults(const ReportSummary& report, const std::vector<ScanRow>& rows,
                        bool with_truth, const std::string& no_plots) {
  std::vector<double> us;
  for (const ScanRow& r : rows) us.push_back(r.total_us);
  const Summary t = summarize(us);
  std::ostringstream html;
  html << "<h2>Results</h2>\n<table id=\"results\">\n<tr><th>scans</th><th>path length (m)</th>"
       << "<th>failed matches</th><th>final error vs ground truth (m)</th><th>time per scan, "
          "median (&micro;s)</th>"
       << "<th>p99 (&micro;s)</th><th>max (&micro;s)</th></tr>\n<tr><td>" << report.scans
       << "</td><td>" << fixed(report.length_m, 2) << "</td><td>" << report.failed_matches
       << "</td><td>"
       << (report.final_error_m       ? fixed(*report.final_error_m, 3)
           : report.truth_problem.empty() ? std::string("no ground truth")
                                          : std::string("ground truth left out"))
       << "</td><td>" << fixed(t.median, 1) << "</td><td>" << fixed(t.p99, 1) << "</td><td>"
       << fixed(t.max, 1) << "</td></tr>\n</table>\n";
  if (!report.truth_problem.empty()) html << "<p>Ground truth left out: " << escapeXml(report.truth_problem) << "</p>\n";
  if (!no_plots.empty()) {
    html << "<p>No plots: " << escapeXml(no_plots) << "</p>\n";
    return html.str();
  }
  html << "<h2>Trajectory</h2>\n<img src=\"trajectory.png\" alt=\"trajectories\">\n"
       << "<h2>" << (with_truth ? "Error over time" : "Match uncertainty over time") << "</h2>\n"
       << "<img src=\"error_over_time.png\" alt=\"error over time\">\n"
       << "<h2>Timing</h2>\n<img src=\"timing.png\" alt=\"timing histogram\">\n";
  return html.str();
}

// The table of the gallery's scans, worst first, then their pictures.
std::string htmlGallery(const std::vector<ScanRow>& rows, const std::vector<std::size_t>& gallery) {
  std::ostringstream html;
  html << "<h2>Worst-matched scans first</h2>\n<table id=\"worst\">\n<tr><th>scan</th><th>t "
          "(s)</th><th>status</th>"
       << "<th>pairs</th><th>sd (m)</th><th>increment error (m)</th><th>features</th></tr>\n";
  for (std::size_t i : gallery) {
    const ScanRow& r = rows[i];
    html << "<tr><td><a href=\"#scan" << i << "\">" << i << "</a></td><td>"
         << fixed(r.t - rows.front().t, 2) << "</td><td>" << r.status << "</td><td>" << r.matches
         << "</td><td>" << fixed(r.sd_xy_m, 4) << "</td><td>" << fixed(r.error_m, 4) << "</td><td>"
         << r.features << "</td></tr>\n";
  }
  html << "</table>\n<h2>Gallery</h2>\n";
  for (std::size_t i : gallery) {
    html << "<figure id=\"scan" << i << "\"><img src=\"frames/scan_" << i << ".png\" alt=\"scan "
         << i << "\"><figcaption>scan " << i << ": " << rows[i].status << ", " << rows[i].matches
         << " pairs"
         << (std::isfinite(rows[i].error_m)
                 ? ", increment error " + fixed(rows[i].error_m, 3) + " m"
                 : std::string())
         << "</figcaption></figure>\n";
  }
  return html.str();
}

// The end of the page: a script that counts the images loaded, into a hidden element that
// the tests read (the reader never sees it).
const char* const kHtmlFooter =
    "<p id=\"image-check\" hidden>images not checked</p>\n"
    "<script>window.addEventListener('load',function(){var ok=0,bad=0;"
    "document.querySelectorAll('img').forEach(function(i){if(i.complete&&i.naturalWidth>0)ok++;"
    "else bad++;});"
    "document.getElementById('image-check').textContent='images loaded='+ok+' "
    "broken='+bad;});</script>\n"
    "</body></html>\n";

// The frames of the gallery are drawn with these layers unless --layers says otherwise.
constexpr const char* kGalleryLayers = "raw,l1,l3,predicted,matches,features,trajectory,camera";

// trajectory.png: lidarseg's path and every reference's from its pose at the first scan.
std::string trajectoryPlot(const std::vector<ScanRow>& rows, const std::vector<Reference>& references) {
  std::vector<PlotSeries> series;
  PlotSeries mine = makeSeries("lidarseg", report::kLidarsegColour);
  for (const ScanRow& r : rows) mine.x.push_back(r.pose.x), mine.y.push_back(r.pose.y);
  series.push_back(mine);
  std::vector<std::string> names;
  for (const auto& ref : references) names.push_back(ref.name);
  const std::vector<report::Rgb> colours = report::referenceColours(names);
  for (std::size_t i = 0; i < references.size(); ++i) {
    const Reference& ref = references[i];
    PlotSeries s = makeSeries(ref.name, colours[i]);
    // A reference with no pose near the log's first scan keeps its legend entry, "(no data)".
    const auto first = eval::nearestIndex(ref.poses, rows.front().t, 1.0);
    for (std::size_t k = first.value_or(ref.poses.size()); k < ref.poses.size() && ref.poses[k].stamp_s <= rows.back().t + 1e-6; ++k) {
      const Pose2D a = relative(ref.poses[k].pose, ref.poses[*first].pose);
      s.x.push_back(a.x), s.y.push_back(a.y);
    }
    series.push_back(s);
  }
  return plotTrajectoriesPng(series, "Trajectories (odometry frame)");
}

// error_over_time.png: the position error against the truth, or without one the match sd.
std::string errorPlot(const std::vector<ScanRow>& rows, bool with_truth) {
  PlotSeries over_time = makeSeries(with_truth ? "lidarseg: position error against the ground truth" : "lidarseg: match sd",
                                    report::kLidarsegColour);
  for (const ScanRow& r : rows) {
    const double v = with_truth ? r.drift_m : r.sd_xy_m;
    if (std::isfinite(v)) over_time.x.push_back(r.t - rows.front().t), over_time.y.push_back(v);
  }
  return plotXYPng({over_time}, with_truth ? "Position error over time" : "Match uncertainty over time", "time (s)",
                   with_truth ? "error (m)" : "sd (m)");
}

// timing.png: the histogram of the time per scan.
std::string timingPlot(const std::vector<ScanRow>& rows) {
  PlotSeries times = makeSeries("lidarseg: W-D + cascade + matching", report::kLidarsegColour);
  for (const ScanRow& r : rows) {
    if (r.total_us > 0) times.x.push_back(r.total_us);
  }
  return plotHistogramsPng({times}, "Time per scan", "microseconds");
}

}  // namespace

const eval::StampedTrajectory* groundTruth(const Session& session) {
  const eval::StampedTrajectory* truth = nullptr;
  for (const auto& r : session.references()) {
    if (r.name == "ground truth") truth = &r.poses;
  }
  return truth;
}

std::vector<ScanRow> scanRows(Session& session, const eval::StampedTrajectory* truth,
                              bool show_progress) {
  const std::size_t n = session.countAll();
  const auto traj = session.trajectory(n - 1);
  std::vector<ScanRow> rows;
  rows.reserve(n);
  report::Progress progress("lidarseg-inspect", show_progress, n);
  for (std::size_t i = 0; i < n; ++i) {
    rows.push_back(scanRow(session.frame(i), traj[i]));
    progress.update(i + 1);
  }
  progress.done(n);
  if (truth) compareWithTruth(rows, *truth, session.mountOfFirstScan());
  return rows;
}

ReportSummary summarizeRows(const std::vector<ScanRow>& rows) {
  ReportSummary report;
  report.scans = rows.size();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    report.failed_matches += rows[i].failed;
    if (i > 0)
      report.length_m +=
          std::hypot(rows[i].pose.x - rows[i - 1].pose.x, rows[i].pose.y - rows[i - 1].pose.y);
  }
  if (std::isfinite(rows.back().drift_m)) report.final_error_m = rows.back().drift_m;
  return report;
}

std::vector<std::size_t> worstFirst(const std::vector<ScanRow>& rows, std::size_t count) {
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), 0);
  const auto badness = [&](std::size_t i) {
    const ScanRow& r = rows[i];
    const double score = std::isfinite(r.error_m) ? r.error_m : r.sd_xy_m;
    return std::make_pair(r.failed ? 1 : 0, score);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return badness(a) > badness(b); });
  order.resize(std::min(order.size(), count));
  return order;
}

std::string reportHtml(const std::string& input, const ReportSummary& summary,
                       const std::vector<ScanRow>& rows, bool with_truth, const std::string& no_plots) {
  return htmlHeader(input) + htmlResults(summary, rows, with_truth, no_plots) +
         htmlGallery(rows, summary.gallery) + kHtmlFooter;
}

}  // namespace lidarseg::inspect

namespace lidarseg::inspect {

std::vector<std::string> reportFileNames() {
  return {"index.html", "trajectory.png", "error_over_time.png", "timing.png"};
}

ReportSummary writeLogReport(Session& session, const ReportSettings& settings) {
  const std::string& dir = settings.dir;
  fs::create_directories(dir + "/frames");
  const eval::StampedTrajectory* truth = groundTruth(session);
  std::vector<ScanRow> rows = scanRows(session, nullptr, settings.progress);
  std::string truth_problem;
  if (truth != nullptr) {
    std::vector<double> stamps;
    stamps.reserve(rows.size());
    for (const ScanRow& r : rows) stamps.push_back(r.t);
    truth_problem = report::truthPairingProblem(settings.truth_path, *truth, stamps, kTruthToleranceS);
    if (truth_problem.empty()) compareWithTruth(rows, *truth, session.mountOfFirstScan());
    else truth = nullptr;
  }
  ReportSummary report = summarizeRows(rows);
  report.truth_problem = std::move(truth_problem);
  report.gallery = worstFirst(rows, settings.gallery);

  report::OutputSet outputs;
  // The gallery of an earlier report of more frames (or others) goes: frames/ is this one's.
  outputs.replaceNumbered(dir, {"frames/scan_", ".png"});
  const Layers layers = parseLayers(settings.layers.empty() ? kGalleryLayers : settings.layers);
  for (std::size_t i : report.gallery) {
    outputs.add(dir + "/frames/scan_" + std::to_string(i) + ".png",
                vision::encodePng(renderPng(session.draw(i, layers), cv::Size(900, 700))));
  }
  // Without gnuplot the report is written without its plots (decision 55).
  try {
    std::vector<std::pair<std::string, std::string>> plots;
    plots.emplace_back("trajectory.png", trajectoryPlot(rows, session.references()));
    plots.emplace_back("error_over_time.png", errorPlot(rows, truth != nullptr));
    plots.emplace_back("timing.png", timingPlot(rows));
    for (auto& [name, png] : plots) outputs.add(dir + "/" + name, std::move(png));
  } catch (const std::runtime_error& e) {
    report.no_plots = e.what();
  }
  outputs.add(dir + "/index.html", reportHtml(settings.input, report, rows, truth != nullptr, report.no_plots));
  outputs.commit();
  return report;
}

}  // namespace lidarseg::inspect
