#include "lidarseg/apps/OdometryApp.h"

#include "lidarseg/apps/CommandLine.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "lidarseg/report/FeatureCsv.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/pipeline/ReadRecords.h"
#include "lidarseg/report/RecordGate.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/pipeline/OdometryRun.h"
#include "lidarseg/pipeline/RawlogWriter.h"
#include "lidarseg/report/RunEvaluation.h"
#include "lidarseg/report/ReportWriters.h"

namespace lidarseg::apps {

using report::installCleanupOnSignals;
using report::refuseOverwritingInput;
using report::OutputSet;


namespace fs = std::filesystem;

OdometryApp::OdometryApp(OdometryOptions options) : options_(std::move(options)) {}

namespace {
// The baselines the options ask for, by name.
std::vector<std::string> baselinesOf(const OdometryOptions& o) {
  std::vector<std::string> names;
  if (o.baseline_icp) names.emplace_back("icp");
  if (o.baseline_icp_s2s) names.emplace_back("icp-s2s");
  return names;
}

// The configuration file's sections, then the command line's overrides.
pipeline::RunSettings settingsOf(const OdometryOptions& o) {
  pipeline::RunSettings s;
  if (!o.config_path.empty()) s.config = mrpt_adapter::LidarsegConfig::loadFile(o.config_path);
  if (o.scanner_rotation_hz) s.config.odometry.scanner_rotation_hz = *o.scanner_rotation_hz;
  if (!o.scan_stamp.empty()) s.config.odometry.scan_stamp = scanStampFromString(o.scan_stamp);
  s.config.odometry.validate();
  // The stamped beam only places the beams' instants for the rolling-shutter correction:
  // without it the option would change nothing, without a word (issue 16).
  if (!o.scan_stamp.empty() && !(s.config.odometry.scanner_rotation_hz > 0.0)) {
    throw UsageError("--scan-stamp " + o.scan_stamp +
                     " places the beams for the rolling-shutter correction, which is off: give --scanner-hz (or "
                     "[odometry] scanner_rotation_hz in the configuration)");
  }
  s.use_odometry = o.use_odometry;
  s.baselines = baselinesOf(o);
  return s;
}
}  // namespace

namespace {

// The options' values, checked before anything is read or written (usage errors).
void checkOptions(const OdometryOptions& o) {
  if (!o.scan_stamp.empty()) checkedOption("--scan-stamp", [&] { (void)scanStampFromString(o.scan_stamp); });
  if (const auto hz = o.scanner_rotation_hz; hz && !(*hz == 0.0 || (*hz >= kMinScannerHz && *hz <= kMaxScannerHz))) {
    throw UsageError("--scanner-hz must be 0 (no correction) or from " + numberText(kMinScannerHz) + " to " +
                     numberText(kMaxScannerHz) + " Hz (got " + numberText(*hz) + ")");
  }
  // Freiburg relations are at most a few seconds apart: a tolerance of a second or more pairs
  // a relation with unrelated scans, and 0 or less pairs none.
  if (!(o.relations_tolerance_s > 0.0 && o.relations_tolerance_s <= kMaxRelationsToleranceS)) {
    throw UsageError("--relations-tolerance must be above 0 and at most " + numberText(kMaxRelationsToleranceS) +
                     " s (got " + numberText(o.relations_tolerance_s) + ")");
  }
  if (o.write_landmarks && o.write_rawlog.empty()) {
    throw UsageError("--write-landmarks adds landmarks to the rawlog of --write-rawlog, which is not given");
  }
}

}  // namespace

OdometryReport OdometryApp::run() {
  const OdometryOptions& o = options_;
  checkOptions(o);
  gt_path_ = o.gt_path.empty() && o.auto_gt ? report::groundTruthBeside(o.input) : o.gt_path;
  OutputSet outputs;
  claimOutputs(outputs);  // before anything is read
  const pipeline::RunSettings settings = settingsOf(o);
  report::RunReferences refs = readReferences();
  mrpt_adapter::LaserLogReader reader(o.input, o.sensor);
  pipeline::OdometryRun odometry(settings);
  processLog(reader, odometry, settings, outputs);
  OdometryReport report = odometry.finish(o.max_lost_ratio);
  collectReaderCounts(reader, report);
  report::evaluateRun({&odometry.logPoses(), odometry.medianStep()}, refs, o.log_reference, o.relations_tolerance_s,
                      report);
  writeOutputs(report, refs, odometry.logPoses(), odometry.wheelOdometry(), outputs);
  return report;
}

// Every output refused when it is the input, its folder locked against a second run, and
// temporary files removed on SIGINT/SIGTERM.
void OdometryApp::claimOutputs(OutputSet& outputs) const {
  const OdometryOptions& o = options_;
  installCleanupOnSignals();
  // The inputs are also what the publishing of the -o folder never removes. Every file this
  // run may write in the folder is checked against the inputs and the other outputs.
  outputs.claimOutputs({{o.write_rawlog, "--write-rawlog"}, {o.features_out, "--features-out"}},
                       {{o.out_dir, "-o", report::runOutputNames(baselinesOf(o), o.plots)}},
                       {o.input, gt_path_, o.relations_path, o.config_path});
}

// Ground truth (PREFIX.gt.tum beside the input unless given) and relations files.
report::RunReferences OdometryApp::readReferences() {
  return report::readRunReferences(gt_path_, options_.relations_path);
}

// Every scan through the run; doors and corners and the rawlog output beside it.
void OdometryApp::processLog(mrpt_adapter::LaserLogReader& reader, pipeline::OdometryRun& odometry,
                             const pipeline::RunSettings& settings, OutputSet& outputs) {
  const OdometryOptions& o = options_;
  const bool want_features = !o.features_out.empty() || o.write_landmarks;
  const FeatureDetector detector(settings.config.features);
  std::vector<Feature> features;
  std::ostringstream features_csv;
  report::writeFeatureCsvHeader(features_csv);
  std::optional<pipeline::RawlogWriter> rawlog;
  if (!o.write_rawlog.empty()) rawlog.emplace(o.write_rawlog, outputs, o.write_landmarks);
  const auto use = [&](const mrpt_adapter::LaserRecord& record) {
    const pipeline::RunStep step = odometry.process(record);
    if (!step.processed) return;
    if (want_features) {
      detector.detect(odometry.lidarseg().core().lastSegmentation(), features);
      if (!o.features_out.empty()) {
        report::writeFeatureCsvRows(features_csv, step.time.output_stamp_s, record.index, record.sensor_on_robot,
                                      features);
      }
    }
    if (rawlog) rawlog->write(record, odometry.lidarseg().lastStep(), step.time.output_stamp_s, features);
  };
  log_error_ = pipeline::readRecords(reader, odometry.counts(),
                                     {"lidarseg-odometry", o.sensor, o.max_scans, o.progress, o.allow_truncated}, use);
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
  pipeline::addReaderCounts(reader, report);
}


// Trajectories, timings, summary, table and pictures, all put in place together.
void OdometryApp::writeOutputs(OdometryReport& report, const report::RunReferences& refs, const eval::StampedTrajectory& log_poses,
                               const eval::StampedTrajectory& wheel_odometry, OutputSet& outputs) const {
  const OdometryOptions& o = options_;
  if (!o.out_dir.empty()) {
    const std::vector<std::string> written = report::addRunOutputs(outputs, o.out_dir, report, log_poses, wheel_odometry);
    if (o.plots) {
      try {
        report::addRunPlots(outputs, o.out_dir, report, refs, log_poses, wheel_odometry,
                              fs::path(o.input).filename().string());
      } catch (const std::runtime_error& e) {
        std::cerr << "lidarseg-odometry: warning: no pictures: " << e.what() << "\n";
      }
    }
    report.outputs = written;
  }
  outputs.commit();
  if (!o.features_out.empty()) report.outputs.push_back(o.features_out);
  if (!o.write_rawlog.empty()) report.outputs.push_back(o.write_rawlog);
}

}  // namespace lidarseg::apps
