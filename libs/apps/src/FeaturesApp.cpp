#include "lidarseg/apps/FeaturesApp.h"

#include "lidarseg/apps/CommandLine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "lidarseg/mrpt/CameraRois.h"
#include "lidarseg/report/FeatureCsv.h"
#include "lidarseg/report/Plots.h"
#include "lidarseg/pipeline/ReadRecords.h"
#include "lidarseg/report/RecordGate.h"
#include "ReportTools.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"

namespace lidarseg::apps {

using mrpt_adapter::CameraRois;
using mrpt_adapter::drawRois;
using mrpt_adapter::writeRoiCsvHeader;
using mrpt_adapter::writeRoiCsvRows;
using report::scanFeaturesPng;

namespace {

// One configuration, every section optional; the defaults without a file.
mrpt_adapter::LidarsegConfig loadConfig(const std::string& path) {
  return path.empty() ? mrpt_adapter::LidarsegConfig() : mrpt_adapter::LidarsegConfig::loadFile(path);
}

// Size of the image the regions cover (pixels): the configured camera's, else the image's own.
cv::Size imageSize(const mrpt::obs::CObservationImage& image, const std::optional<vision::CameraParams>& camera) {
  if (camera) return {camera->width, camera->height};
  return {static_cast<int>(image.cameraParams.ncols), static_cast<int>(image.cameraParams.nrows)};
}

// The last scan processed: a camera image is given the features of the scan before it.
struct LastScan {
  std::size_t index = 0;
  mrpt::poses::CPose3D lidar_on_robot;
  std::vector<Feature> features;
};

// One pass over the log: each scan's features detected, timed, written and scored, and each
// camera image given the regions of the features of the scan before it.
class LogPass {
 public:
  // Throws for an invalid configuration or an unreadable ground truth.
  LogPass(const FeaturesOptions& options, const mrpt_adapter::LidarsegConfig& config, FeaturesReport& report,
          OutputSet& outputs)
      : options_(options),
        camera_(config.vision.camera),
        camera_rois_(options.input, config.vision.camera, config.vision.rois),
        segmenter_(config.odometry.segmentation),
        detector_(config.features),
        report_(report),
        outputs_(outputs) {
    if (!options.truth_path.empty()) {
      truth_ = eval::readTrueFeatures(options.truth_path);
      report.evaluation.emplace(options.gate_m);
    }
    report::writeFeatureCsvHeader(csv_);
    if (!options.matches_out.empty()) eval::writeMatchesCsvHeader(matches_csv_);
    writeRoiCsvHeader(rois_csv_);
  }

  // The regions of interest of the record's camera images (paper Fig. 7).
  void addImages(const mrpt_adapter::LaserRecord& record) {
    for (const auto& obs : record.companions) {
      const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obs);
      if (!image) continue;
      const std::size_t n = report_.images++;
      if (last_) addImage(record, *image, n);
    }
  }

  // The record's scan at its run's stamp: segmented, its features detected (both timed),
  // counted, written and scored. @throws std::invalid_argument for a scan that cannot be
  // segmented (the gate skips it).
  void addScan(const mrpt_adapter::LaserRecord& record, const StampStep& time) {
    const Scan& scan = record.scan;
    auto t0 = Clock::now();
    segmenter_.process(scan, segmentation_);
    const double segment_us = microsecondsSince(t0);
    t0 = Clock::now();
    detector_.detect(segmentation_, features_);
    detect_us_.push_back(microsecondsSince(t0));
    segment_us_.push_back(segment_us);
    report_.beams_per_scan = std::max(report_.beams_per_scan, scan.size());
    ++report_.scans;

    // Features are in the sensor frame; the CSV speaks of the robot frame.
    const mrpt::poses::CPose3D sp = mrpt_adapter::sensorPose3D(record);
    last_ = LastScan{record.index, sp, features_};
    for (const Feature& f : features_) ++report_.detections[static_cast<std::size_t>(f.type)];
    report::writeFeatureCsvRows(csv_, time.output_stamp_s, record.index, {sp.x(), sp.y(), sp.yaw()}, features_);
    if (report_.evaluation) score(record.index, record.stamp_s);
    if (options_.figure_scan && *options_.figure_scan == record.index) drawFigure(record.index);
  }

  // The per-scan and per-image samples summarised into the report; a truth that is not
  // this log's (stamped otherwise, or for no scan read) is named in a warning.
  void summarise() {
    if (report_.evaluation && truth_scans_ == 0) {
      report_.warnings.push_back("--gt " + options_.truth_path + ": no scan read has truth (the truth of another log?); "
                                 "the figures measure nothing");
    } else if (truth_mismatches_ > 0) {
      report_.warnings.push_back("--gt " + options_.truth_path + ": the truth of " + std::to_string(truth_mismatches_) +
                                 " of " + std::to_string(truth_scans_) + " scans is stamped more than 1 ms from the scan "
                                 "of its number (the truth of another log?), the first: " + first_mismatch_);
    }
    report_.detect_us = summarize(detect_us_);
    report_.segment_us = summarize(segment_us_);
    report_.position_error_m = summarize(errors_);
    report_.roi_coverage = summarize(coverage_);
  }

  // The features CSV and the regions CSV, header included.
  std::string csv() const { return csv_.str(); }
  std::string roisCsv() const { return rois_csv_.str(); }
  std::string matchesCsv() const { return matches_csv_.str(); }
  // Whether the --figure-scan scan was met in the log (drawn, or warned about).
  bool figureMet() const { return figure_met_; }
  // Why gnuplot failed to draw the figure (empty: drawn, or not asked for).
  const std::string& figureError() const { return figure_error_; }

 private:
  // Image n: its regions as CSV rows and coverage and, when asked, drawn on its pixels; an
  // unusable calibration or unreadable pixels skip it.
  void addImage(const mrpt_adapter::LaserRecord& record, const mrpt::obs::CObservationImage& image, std::size_t n) {
    const auto skip = [&](const std::exception& e) {
      ++report_.skipped_count;
      report_.skipped.push_back(record.where + ": image " + std::to_string(n) + ": " + e.what());
    };
    std::vector<vision::Roi> rois;
    try {
      rois = camera_rois_.project(image, last_->lidar_on_robot, last_->features);
    } catch (const std::invalid_argument& e) {
      skip(e);
      return;
    }
    writeRoiCsvRows(rois_csv_, n, last_->index, mrpt::Clock::toDouble(image.timestamp), CameraRois::fileOf(image),
                    rois);
    std::vector<cv::Rect> boxes;
    for (const vision::Roi& r : rois) boxes.push_back(r.box);
    coverage_.push_back(vision::coveredFraction(boxes, imageSize(image, camera_)));
    report_.rois += rois.size();
    if (!rois.empty()) ++report_.images_with_rois;
    if (options_.images_out.empty()) return;
    cv::Mat bgr;
    try {
      bgr = camera_rois_.pixels(image);
    } catch (const std::runtime_error& e) {
      skip(e);
      return;
    }
    drawRois(bgr, rois);
    char name[32];
    std::snprintf(name, sizeof(name), "rois_%06zu.png", n);
    outputs_.add(options_.images_out + "/" + name, encodePng(bgr));
  }

  // The detections against the truth; the simulator's truth is in the robot frame, which is
  // its lidar's frame.
  void score(std::size_t scan, double stamp_s) {
    static const std::vector<eval::TrueFeature> kNone;
    const auto it = truth_.find(scan);
    const auto& truth = it == truth_.end() ? kNone : it->second;
    if (!truth.empty()) {
      ++truth_scans_;
      if (std::abs(truth.front().stamp_s - stamp_s) > kTruthStampToleranceS && truth_mismatches_++ == 0) {
        first_mismatch_ = "scan " + std::to_string(scan) + " at " + numberText(stamp_s) + " s, its truth at " +
                          numberText(truth.front().stamp_s) + " s";
      }
    }
    const auto e = report_.evaluation->add(truth, features_);
    errors_.insert(errors_.end(), e.begin(), e.end());
    if (!options_.matches_out.empty()) eval::writeMatchesCsvRows(matches_csv_, scan, truth, features_, *report_.evaluation);
  }

  // Paper Fig. 6 of this scan, published with the other outputs; without gnuplot a warning
  // and no file (decision 55), the run goes on; gnuplot failing is the run's error.
  void drawFigure(std::size_t scan) {
    figure_met_ = true;
    const std::string title =
        "scan " + std::to_string(scan) + " of " + std::filesystem::path(options_.input).filename().string();
    std::string png;
    try {
      png = scanFeaturesPng(report::scanPictureOf(segmentation_, detector_.params().level, features_), title);
    } catch (const report::PlotterMissing& e) {
      report_.warnings.push_back("no figure " + options_.figure_path + ": " + e.what());
      return;
    } catch (const std::runtime_error& e) {
      figure_error_ = e.what();  // an error once the other outputs are written
      return;
    }
    // Published with the run's other outputs, never before (an interrupted run replaces
    // nothing).
    outputs_.add(options_.figure_path, std::move(png));
  }

  const FeaturesOptions& options_;
  const std::optional<vision::CameraParams> camera_;
  const CameraRois camera_rois_;
  const ScanSegmenter segmenter_;
  const FeatureDetector detector_;
  std::map<std::size_t, std::vector<eval::TrueFeature>> truth_;  // by scan index
  // How far a truth's stamp may be from its scan's (s): the simulator writes both from one
  // clock, at microsecond resolution or finer.
  static constexpr double kTruthStampToleranceS = 1e-3;
  std::size_t truth_scans_ = 0, truth_mismatches_ = 0;
  std::string first_mismatch_;
  FeaturesReport& report_;
  OutputSet& outputs_;
  Segmentation segmentation_;
  std::vector<Feature> features_;
  std::optional<LastScan> last_;
  std::ostringstream csv_, rois_csv_, matches_csv_;
  std::vector<double> detect_us_, segment_us_, errors_, coverage_;
  bool figure_met_ = false;
  std::string figure_error_;
};

// The CSV files and the report put in place, together with the images drawn during the pass.
void writeOutputs(const FeaturesOptions& options, const FeaturesReport& report, const LogPass& pass,
                  OutputSet& outputs) {
  if (!options.out_csv.empty()) outputs.add(options.out_csv, pass.csv());
  if (!options.rois_out.empty()) outputs.add(options.rois_out, pass.roisCsv());
  if (!options.matches_out.empty()) outputs.add(options.matches_out, pass.matchesCsv());
  if (!options.report_dir.empty()) {
    std::filesystem::create_directories(options.report_dir);
    outputs.add(options.report_dir + "/features.md", report::featuresMarkdown(report));
    outputs.add(options.report_dir + "/features.json", report::featuresJson(report));
  }
  outputs.commit();
}

}  // namespace

FeaturesApp::FeaturesApp(FeaturesOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw UsageError("no input log given");
  if (options_.figure_scan && options_.figure_path.empty()) {
    throw UsageError("--figure-scan needs --figure FILE.png");
  }
  if (!options_.matches_out.empty() && options_.truth_path.empty()) throw UsageError("--matches-out needs --gt");
  if (options_.gate_given && options_.truth_path.empty()) throw UsageError("--gate needs --gt (it gates the match against the truth)");
  if (!(options_.gate_m > 0.0 && options_.gate_m <= 1e6)) {
    throw UsageError("--gate must be a distance > 0 m (got " + numberText(options_.gate_m) + ")");
  }
}

namespace {

// Before any work: an output that is an input is refused, a second writer at once.
void claimOutputs(const FeaturesOptions& o, OutputSet& outputs) {
  outputs.claimOutputs({{o.out_csv, "--out"},
                        {o.rois_out, "--rois-out"},
                        {o.figure_path, "--figure"},
                        {o.matches_out, "--matches-out"}},
                       {{o.report_dir, "--report", {"features.md", "features.json"}}, {o.images_out, "--images-out", {}, {{"rois_", ".png"}}}},
                       {o.input, o.config_path, o.truth_path});
  if (!o.images_out.empty()) std::filesystem::create_directories(o.images_out);
}

// Every record of the log through the run's gate into the pass (up to max_scans scans),
// with progress on stderr; what the gate and the reader skipped is listed in the report.
void readLog(const FeaturesOptions& o, const mrpt_adapter::LidarsegConfig& config, LogPass& pass,
             FeaturesReport& report) {
  mrpt_adapter::LaserLogReader reader(o.input, o.sensor_label);
  report::RecordGate gate(config.stamps);
  const auto use = [&](const mrpt_adapter::LaserRecord& record) {
    gate.pass(record, [&](const StampStep& time) { pass.addScan(record, time); });
  };
  const auto images = [&](const mrpt_adapter::LaserRecord& record) { pass.addImages(record); };
  pipeline::readRecords(reader, gate.counts(), {"lidarseg-features", o.sensor_label, o.max_scans, o.progress}, use,
                        images);
  report::RecordCounts counts = gate.counts();
  pipeline::addReaderCounts(reader, counts);
  report.skipped.insert(report.skipped.end(), counts.skipped.begin(), counts.skipped.end());
  report.skipped_count += counts.skipped_count;
  report.stamps = counts;
  report.log_warnings = counts.warnings;
  report.log_warning_kinds = counts.warning_kinds;
}

// The figure the user asked for is the run's result as much as the tables: a scan beyond
// the log is an error (as `lidarseg-inspect -f` beyond the log is), raised once the other
// outputs are written so that nothing else is lost.
void requireFigure(const FeaturesOptions& o, const LogPass& pass, const FeaturesReport& report) {
  if (!pass.figureError().empty()) {
    throw std::runtime_error("--figure '" + o.figure_path + "' not written: " + pass.figureError() +
                             "; the other outputs are");
  }
  if (!o.figure_scan || pass.figureMet()) return;
  throw std::runtime_error("--figure-scan " + std::to_string(*o.figure_scan) + ": no such scan among the " +
                           std::to_string(report.scans) + " scans read from " + o.input + " (scans count from 0); " +
                           o.figure_path + " not written, the other outputs are");
}

}  // namespace

FeaturesReport FeaturesApp::run() {
  OutputSet outputs;
  claimOutputs(options_, outputs);
  const mrpt_adapter::LidarsegConfig config = loadConfig(options_.config_path);
  FeaturesReport report;
  report.input = options_.input;
  LogPass pass(options_, config, report, outputs);
  readLog(options_, config, pass, report);
  pass.summarise();
  writeOutputs(options_, report, pass, outputs);
  requireFigure(options_, pass, report);
  return report;
}

void FeaturesApp::print(const FeaturesReport& report, std::ostream& os) { os << report::featuresMarkdown(report); }

void FeaturesApp::printWarnings(const FeaturesReport& report, std::ostream& err) {
  const std::string tool = "lidarseg-features: warning: ";
  report::printRecordWarnings(report.log_warning_kinds, "lidarseg-features", err);
  for (const std::string& w : report.warnings) err << tool << w << '\n';
  if (!report.skipped.empty()) {
    err << tool << report.skipped_count << " scans or images skipped, the first: " << report.skipped.front() << '\n';
  }
}

}  // namespace lidarseg::apps
