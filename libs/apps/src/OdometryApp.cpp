#include "lidarseg/apps/OdometryApp.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "lidarseg/pipeline/FeatureCsv.h"
#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/pipeline/Plots.h"
#include "lidarseg/pipeline/Progress.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/pipeline/OdometryRun.h"
#include "lidarseg/pipeline/RawlogWriter.h"
#include "lidarseg/pipeline/RunEvaluation.h"
#include "lidarseg/pipeline/ReportWriters.h"

namespace lidarseg::apps {

using pipeline::installCleanupOnSignals;
using pipeline::refuseOverwritingInput;
using pipeline::OutputSet;

using pipeline::Progress;
using pipeline::makeSeries;
using pipeline::plotHistogramsPng;
using pipeline::plotTrajectoriesPng;
using pipeline::PlotSeries;

namespace fs = std::filesystem;

namespace {

std::string inputName(const std::string& path) { return fs::path(path).filename().string(); }

}  // namespace

OdometryApp::OdometryApp(OdometryOptions options) : options_(std::move(options)) {}

namespace {
// The configuration file's sections, then the command line's overrides.
pipeline::RunSettings settingsOf(const OdometryOptions& o) {
  pipeline::RunSettings s;
  if (!o.config_path.empty()) s.config = mrpt_adapter::LidarsegConfig::loadFile(o.config_path);
  if (o.scanner_rotation_hz >= 0.0) s.config.odometry.scanner_rotation_hz = o.scanner_rotation_hz;
  if (!o.scan_stamp.empty()) s.config.odometry.scan_stamp = scanStampFromString(o.scan_stamp);
  s.config.odometry.validate();
  s.use_odometry = o.use_odometry;
  s.icp_keyframed = o.baseline_icp;
  s.icp_scan_to_scan = o.baseline_icp_s2s;
  return s;
}
}  // namespace

OdometryReport OdometryApp::run() {
  const OdometryOptions& o = options_;
  const pipeline::RunSettings settings = settingsOf(o);
  pipeline::RunReferences refs = readReferences();
  OutputSet outputs;
  claimOutputs(outputs);
  mrpt_adapter::LaserLogReader reader(o.input, o.sensor);
  pipeline::OdometryRun odometry(settings);
  processLog(reader, odometry, settings, outputs);
  OdometryReport report = odometry.finish(o.max_lost_ratio);
  collectReaderCounts(reader, report);
  pipeline::evaluateRun(odometry, refs, o.log_reference, o.relations_tolerance_s, report);
  writeOutputs(report, refs, odometry.logPoses(), odometry.wheelOdometry(), outputs);
  return report;
}

// Every output refused when it is the input, its folder locked against a second run, and
// temporary files removed on SIGINT/SIGTERM.
void OdometryApp::claimOutputs(OutputSet& outputs) const {
  const OdometryOptions& o = options_;
  installCleanupOnSignals();
  if (o.write_landmarks && o.write_rawlog.empty()) {
    throw std::invalid_argument("--write-landmarks adds landmarks to the rawlog of --write-rawlog, which is not given");
  }
  refuseOverwritingInput(o.write_rawlog, o.input, "--write-rawlog");
  refuseOverwritingInput(o.features_out, o.input, "--features-out");
  if (!o.out_dir.empty()) outputs.claim((fs::path(o.out_dir) / "summary.json").string());
  if (!o.write_rawlog.empty()) outputs.claim(o.write_rawlog);
  if (!o.features_out.empty()) outputs.claim(o.features_out);
}

// Ground truth (PREFIX.gt.tum beside the input unless given) and relations files.
pipeline::RunReferences OdometryApp::readReferences() {
  gt_path_ = options_.gt_path.empty() && options_.auto_gt ? pipeline::groundTruthBeside(options_.input) : options_.gt_path;
  return pipeline::readRunReferences(gt_path_, options_.relations_path);
}

namespace {
// A log with no usable scan, and why: the first lines or scans the reader skipped, with
// their place.
std::runtime_error noUsableScan(const OdometryOptions& o, const mrpt_adapter::LaserLogReader& reader) {
  std::string why;
  for (std::size_t k = 0; k < std::min<std::size_t>(reader.issues().size(), 3); ++k) why += "; " + reader.issues()[k];
  if (reader.issues().size() > 3) why += "; ... (" + std::to_string(reader.issues().size()) + " skipped in all)";
  return std::runtime_error("'" + o.input + "' holds no usable laser scan" +
                            (o.sensor.empty() ? std::string() : " with sensor '" + o.sensor + "'") + why);
}
}  // namespace

// Every scan through the run; doors and corners and the rawlog output beside it.
void OdometryApp::processLog(mrpt_adapter::LaserLogReader& reader, pipeline::OdometryRun& odometry,
                             const pipeline::RunSettings& settings, OutputSet& outputs) {
  const OdometryOptions& o = options_;
  const bool want_features = !o.features_out.empty() || o.write_landmarks;
  const FeatureDetector detector(settings.config.features);
  std::vector<Feature> features;
  std::ostringstream features_csv;
  pipeline::writeFeatureCsvHeader(features_csv);
  std::optional<pipeline::RawlogWriter> rawlog;
  if (!o.write_rawlog.empty()) rawlog.emplace(o.write_rawlog, outputs, o.write_landmarks);
  Progress progress("lidarseg-odometry", o.progress, o.max_scans);
  while (o.max_scans == 0 || odometry.counts().frames < o.max_scans) {
    std::optional<mrpt_adapter::LaserRecord> record;
    try {
      record = reader.next();
    } catch (const std::runtime_error& e) {
      if (!o.allow_truncated || odometry.counts().frames == 0) throw;
      log_error_ = e.what();  // the scans before it stand
      break;
    }
    if (!record) break;
    const pipeline::RunStep step = odometry.process(*record);
    if (!step.processed) continue;
    if (want_features) {
      detector.detect(odometry.lidarseg().core().lastSegmentation(), features);
      if (!o.features_out.empty()) {
        pipeline::writeFeatureCsvRows(features_csv, step.time.output_stamp_s, record->index, record->sensor_on_robot,
                                      features);
      }
    }
    if (rawlog) rawlog->write(*record, odometry.lidarseg().lastStep(), step.time.output_stamp_s, features);
    progress.update(odometry.counts().frames, reader.fractionRead());
  }
  progress.done(odometry.counts().frames);
  if (odometry.counts().frames == 0) throw noUsableScan(o, reader);
  if (rawlog) rawlog->close();
  if (!o.features_out.empty()) outputs.add(o.features_out, features_csv.str());
}

// What the reader skipped and did not understand.
void OdometryApp::collectReaderCounts(const mrpt_adapter::LaserLogReader& reader, OdometryReport& report) const {
  report.input = options_.input;
  report.format = reader.format() == mrpt_adapter::LogFormat::kRawlog ? "rawlog" : "carmen";
  report.sensor = reader.sensor();
  report.gt_path = gt_path_;
  report.relations_path = options_.relations_path;
  report.log_error = log_error_;
  for (const auto& s : reader.issues()) {
    if (report.skipped.size() < 100) report.skipped.push_back(s);
  }
  report.skipped_count += reader.skipped();
  for (const auto& s : reader.unknownTypes()) report.warnings.push_back(s);
  for (const auto& s : reader.warnings()) report.warnings.push_back(s);
}


// Trajectories, timings, summary, table and pictures, all put in place together.
void OdometryApp::writeOutputs(OdometryReport& report, const pipeline::RunReferences& refs, const eval::StampedTrajectory& log_poses,
                               const eval::StampedTrajectory& wheel_odometry, OutputSet& outputs) const {
  const OdometryOptions& o = options_;
  if (!o.out_dir.empty()) {
    const std::vector<std::string> written = pipeline::addRunOutputs(outputs, o.out_dir, report, log_poses, wheel_odometry);
    if (o.plots) addPlots(report, refs, log_poses, wheel_odometry, outputs);
    report.outputs = written;
  }
  outputs.commit();
  if (!o.features_out.empty()) report.outputs.push_back(o.features_out);
  if (!o.write_rawlog.empty()) report.outputs.push_back(o.write_rawlog);
}

// trajectories.png (every method from where the reference starts) and timing.png.
void OdometryApp::addPlots(const OdometryReport& report, const pipeline::RunReferences& refs, const eval::StampedTrajectory& log_poses,
                           const eval::StampedTrajectory& wheel_odometry, OutputSet& outputs) const {
  const auto path = [&](const char* name) { return (fs::path(options_.out_dir) / name).string(); };
  std::vector<PlotSeries> series;
  // Every trajectory from the reference's pose at lidarseg's first scan.
  const auto add = [&](const std::string& name, const eval::StampedTrajectory& t, pipeline::Rgb colour, const Pose2D& anchor) {
    if (t.empty()) return;
    PlotSeries s = makeSeries(name, colour);
    const Pose2D first_inverse = inverse(t.front().pose);
    for (const auto& p : t) {
      const Pose2D q = compose(anchor, compose(first_inverse, p.pose));
      s.x.push_back(q.x);
      s.y.push_back(q.y);
    }
    series.push_back(std::move(s));
  };
  const eval::StampedTrajectory* reference = refs.gt ? &*refs.gt : (log_poses.empty() ? nullptr : &log_poses);
  Pose2D anchor;
  if (reference != nullptr) {
    const auto k = eval::nearestIndex(*reference, report.lidarseg.trajectory.front().stamp_s, refs.gt_tolerance_s);
    if (k) anchor = (*reference)[*k].pose;
    PlotSeries s = makeSeries(refs.gt ? "ground truth" : "log poses", pipeline::kTruthColour);
    for (const auto& p : *reference) s.x.push_back(p.pose.x), s.y.push_back(p.pose.y);
    series.push_back(std::move(s));
  }
  add("wheel odometry", wheel_odometry, pipeline::kWheelColour, anchor);
  add("lidarseg", report.lidarseg.trajectory, pipeline::kLidarsegColour, anchor);
  if (report.icp) add("MRPT ICP keyframed", report.icp->trajectory, pipeline::kIcpColour, anchor);
  if (report.icp_s2s) add("MRPT ICP scan to scan", report.icp_s2s->trajectory, pipeline::kIcpS2sColour, anchor);
  std::vector<PlotSeries> hist;
  hist.push_back(makeSeries("lidarseg", pipeline::kLidarsegColour));
  hist.back().x = report.lidarseg.time_us;
  if (report.icp) {
    hist.push_back(makeSeries("MRPT ICP keyframed", pipeline::kIcpColour));
    hist.back().x = report.icp->time_us;
  }
  try {
    outputs.add(path("trajectories.png"), plotTrajectoriesPng(series, "Trajectories: " + inputName(options_.input)));
    outputs.add(path("timing.png"), plotHistogramsPng(hist, "Time per scan", "microseconds"));
  } catch (const std::runtime_error& e) {
    std::cerr << "lidarseg-odometry: warning: no pictures: " << e.what() << "\n";
  }
}

}  // namespace lidarseg::apps
