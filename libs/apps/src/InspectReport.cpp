// lidarseg-inspect --report: the page and figures of inspect::LogReport, with the gallery's
// frames and the charts drawn here.
#include <cmath>
#include <filesystem>
#include <iostream>

#include "lidarseg/pipeline/Plots.h"
#include "lidarseg/apps/InspectApp.h"
#include "lidarseg/inspect/Drawing.h"
#include "lidarseg/inspect/LayerSwitches.h"
#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::apps {

using vision::encodePng;

using pipeline::OutputSet;
using pipeline::makeSeries;
using pipeline::plotHistogramsPng;
using pipeline::plotTrajectoriesPng;
using pipeline::plotXYPng;
using pipeline::PlotSeries;

namespace fs = std::filesystem;

using inspect::ScanRow;

namespace {

// The frames of the gallery are drawn with these layers unless --layers says otherwise.
constexpr const char* kGalleryLayers = "raw,l1,l3,predicted,matches,features,trajectory,camera";

// trajectory.png: lidarseg's path and every reference's from its pose at the first scan.
std::string trajectoryPlot(const std::vector<ScanRow>& rows, const std::vector<inspect::Reference>& references) {
  std::vector<PlotSeries> series;
  PlotSeries mine = makeSeries("lidarseg", pipeline::kLidarsegColour);
  for (const ScanRow& r : rows) mine.x.push_back(r.pose.x), mine.y.push_back(r.pose.y);
  series.push_back(mine);
  std::vector<std::string> names;
  for (const auto& ref : references) names.push_back(ref.name);
  const std::vector<pipeline::Rgb> colours = pipeline::referenceColours(names);
  for (std::size_t i = 0; i < references.size(); ++i) {
    const inspect::Reference& ref = references[i];
    PlotSeries s = makeSeries(ref.name, colours[i]);
    const auto first = eval::nearestIndex(ref.poses, rows.front().t, 1.0);
    if (!first) continue;
    for (std::size_t k = *first; k < ref.poses.size() && ref.poses[k].stamp_s <= rows.back().t + 1e-6; ++k) {
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
                                    pipeline::kLidarsegColour);
  for (const ScanRow& r : rows) {
    const double v = with_truth ? r.drift_m : r.sd_xy_m;
    if (std::isfinite(v)) over_time.x.push_back(r.t - rows.front().t), over_time.y.push_back(v);
  }
  return plotXYPng({over_time}, with_truth ? "Position error over time" : "Match uncertainty over time", "time (s)",
                   with_truth ? "error (m)" : "sd (m)");
}

// timing.png: the histogram of the time per scan.
std::string timingPlot(const std::vector<ScanRow>& rows) {
  PlotSeries times = makeSeries("lidarseg: W-D + cascade + matching", pipeline::kLidarsegColour);
  for (const ScanRow& r : rows) {
    if (r.total_us > 0) times.x.push_back(r.total_us);
  }
  return plotHistogramsPng({times}, "Time per scan", "microseconds");
}

}  // namespace

InspectReport InspectApp::writeReport(inspect::Session& session) {
  const std::string& dir = options_.report_dir;
  fs::create_directories(dir + "/frames");
  const eval::StampedTrajectory* truth = inspect::groundTruth(session);
  const std::vector<ScanRow> rows = inspect::scanRows(session, truth, options_.progress);
  InspectReport report = inspect::summarizeRows(rows);
  report.gallery = inspect::worstFirst(rows, options_.gallery);

  OutputSet outputs;
  const inspect::Layers layers = inspect::parseLayers(options_.layers.empty() ? kGalleryLayers : options_.layers);
  for (std::size_t i : report.gallery) {
    outputs.add(dir + "/frames/scan_" + std::to_string(i) + ".png",
                encodePng(inspect::renderPng(session.draw(i, layers), cv::Size(900, 700))));
  }
  // Without gnuplot the report is written without its plots, with a warning (decision 55).
  std::string no_plots;
  try {
    std::vector<std::pair<std::string, std::string>> plots;
    plots.emplace_back("trajectory.png", trajectoryPlot(rows, session.references()));
    plots.emplace_back("error_over_time.png", errorPlot(rows, truth != nullptr));
    plots.emplace_back("timing.png", timingPlot(rows));
    for (auto& [name, png] : plots) outputs.add(dir + "/" + name, std::move(png));
  } catch (const std::runtime_error& e) {
    no_plots = e.what();
    std::cerr << "lidarseg-inspect: warning: no plots in the report: " << no_plots << "\n";
  }
  outputs.add(dir + "/index.html", inspect::reportHtml(options_.input, report, rows, truth != nullptr, no_plots));
  outputs.commit();
  return report;
}

}  // namespace lidarseg::apps
