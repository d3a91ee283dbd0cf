#include "lidarseg/apps/FeaturesApp.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <stdexcept>

#include "CameraRois.h"
#include "Format.h"
#include "Png.h"
#include "FeatureCsv.h"
#include "JsonText.h"
#include "OutputFiles.h"
#include "Plots.h"
#include "Timing.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/FeatureConfig.h"
#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/VisionConfig.h"

namespace lidarseg::apps {

namespace {

}  // namespace

FeaturesApp::FeaturesApp(FeaturesOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw std::invalid_argument("no input log given");
  if (options_.figure_scan && options_.figure_path.empty()) {
    throw std::invalid_argument("--figure-scan needs --figure FILE.png");
  }
}

FeaturesReport FeaturesApp::run() {
  // One configuration, every section optional.
  mrpt_adapter::LidarsegConfig config;
  if (!options_.config_path.empty()) config = mrpt_adapter::LidarsegConfig::loadFile(options_.config_path);
  const CameraRois camera_rois(options_.input, config.vision.camera, config.vision.rois);
  const ScanSegmenter segmenter(config.odometry.segmentation);
  const FeatureDetector detector(config.features);

  FeaturesReport report;
  report.input = options_.input;
  std::map<std::size_t, std::vector<eval::TrueFeature>> truth;
  if (!options_.truth_path.empty()) {
    truth = eval::readTrueFeatures(options_.truth_path);
    report.evaluation.emplace(options_.gate_m);
  }

  mrpt_adapter::LaserLogReader reader(options_.input, options_.sensor_label);
  mrpt_adapter::ScanConverter converter;
  Segmentation segmentation;
  std::vector<Feature> features;
  std::ostringstream csv;
  writeFeatureCsvHeader(csv);
  std::vector<double> detect_us, segment_us, errors;
  static const std::vector<eval::TrueFeature> kNone;
  // The last scan processed: a camera image is given the features of the scan before it.
  struct LastScan {
    std::size_t index = 0;
    mrpt::poses::CPose3D lidar_on_robot;
    std::vector<Feature> features;
  };
  std::optional<LastScan> last;
  std::ostringstream rois_csv;
  writeRoiCsvHeader(rois_csv);
  std::vector<double> coverage;
  OutputSet outputs;
  if (!options_.images_out.empty()) std::filesystem::create_directories(options_.images_out);
  auto handleImages = [&](const mrpt_adapter::LaserRecord& record) {
    for (const auto& obs : record.companions) {
      const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obs);
      if (!image) continue;
      const std::size_t n = report.images++;
      if (!last) continue;
      std::vector<vision::Roi> rois;
      try {
        rois = camera_rois.project(*image, last->lidar_on_robot, last->features);
      } catch (const std::invalid_argument& e) {
        report.skipped.push_back(record.where + ": image " + std::to_string(n) + ": " + e.what());
        continue;
      }
      const std::string file = CameraRois::fileOf(*image);
      writeRoiCsvRows(rois_csv, n, last->index, mrpt::Clock::toDouble(image->timestamp), file, rois);
      std::vector<cv::Rect> boxes;
      for (const vision::Roi& r : rois) boxes.push_back(r.box);
      const auto& cam = image->cameraParams;
      const cv::Size size = config.vision.camera ? cv::Size(config.vision.camera->width, config.vision.camera->height)
                                                 : cv::Size(static_cast<int>(cam.ncols), static_cast<int>(cam.nrows));
      coverage.push_back(vision::coveredFraction(boxes, size));
      report.rois += rois.size();
      if (!rois.empty()) ++report.images_with_rois;
      if (!options_.images_out.empty()) {
        cv::Mat bgr;
        try {
          bgr = camera_rois.pixels(*image);
        } catch (const std::runtime_error& e) {
          report.skipped.push_back(record.where + ": image " + std::to_string(n) + ": " + e.what());
          continue;
        }
        drawRois(bgr, rois);
        char name[32];
        std::snprintf(name, sizeof(name), "rois_%06zu.png", n);
        outputs.add(options_.images_out + "/" + name, encodePng(bgr));
      }
    }
  };
  while (auto record = reader.next()) {
    handleImages(*record);
    if (options_.max_scans > 0 && report.scans >= options_.max_scans) break;
    Scan scan;
    try {
      scan = converter.convert(*record->observation);
    } catch (const std::exception& e) {
      report.skipped.push_back(record->where + ": " + e.what());
      continue;
    }
    report.beams_per_scan = std::max(report.beams_per_scan, scan.size());
    auto t0 = Clock::now();
    segmenter.process(scan, segmentation);
    segment_us.push_back(microsecondsSince(t0));
    t0 = Clock::now();
    detector.detect(segmentation, features);
    detect_us.push_back(microsecondsSince(t0));
    ++report.scans;

    // Features are in the sensor frame; the CSV speaks of the robot frame.
    const auto& sp = record->observation->sensorPose;
    last = LastScan{record->index, sp, features};
    for (const Feature& f : features) ++report.detections[static_cast<std::size_t>(f.type)];
    writeFeatureCsvRows(csv, record->stamp_s, record->index, {sp.x(), sp.y(), sp.yaw()}, features);
    if (report.evaluation) {
      // The simulator's truth is in the robot frame, which is its lidar's frame.
      const auto it = truth.find(record->index);
      const auto e = report.evaluation->add(it == truth.end() ? kNone : it->second, features);
      errors.insert(errors.end(), e.begin(), e.end());
    }
    if (options_.figure_scan && *options_.figure_scan == record->index) {
      ScanPicture pic;
      for (const auto& q : segmentation.points) {
        if (std::isfinite(q.x())) pic.points.emplace_back(q.x(), q.y());
      }
      for (const Segment& sg : segmentation.level(detector.params().level).segments) {
        pic.segments.push_back({sg.start.x(), sg.start.y(), sg.end.x(), sg.end.y()});
      }
      for (const Feature& f : features) {
        if (isDoor(f.type)) {
          pic.doors.emplace_back(f.position.x(), f.position.y());
          pic.door_jambs.push_back({f.jamb_a.x(), f.jamb_a.y(), f.jamb_b.x(), f.jamb_b.y()});
        } else {
          pic.corners.emplace_back(f.position.x(), f.position.y());
        }
      }
      writeFileAtomically(options_.figure_path,
                          scanFeaturesPng(pic, "scan " + std::to_string(record->index) + " of " +
                                                   std::filesystem::path(options_.input).filename().string()));
    }
  }
  if (report.scans == 0) throw std::runtime_error(options_.input + ": no laser scan read");
  for (const std::string& issue : reader.issues()) report.skipped.push_back(issue);
  report.detect_us = summarize(detect_us);
  report.segment_us = summarize(segment_us);
  report.position_error_m = summarize(errors);
  report.roi_coverage = summarize(coverage);

  if (!options_.out_csv.empty()) outputs.add(options_.out_csv, csv.str());
  if (!options_.rois_out.empty()) outputs.add(options_.rois_out, rois_csv.str());
  if (!options_.report_dir.empty()) {
    std::filesystem::create_directories(options_.report_dir);
    outputs.add(options_.report_dir + "/features.md", markdown(report));
    Json json{{"input", report.input},
              {"scans", report.scans},
              {"detect_us_median", finiteOrNull(report.detect_us.median)},
              {"segment_us_median", finiteOrNull(report.segment_us.median)},
              {"images", report.images},
              {"images_with_rois", report.images_with_rois},
              {"rois", report.rois},
              {"roi_coverage_median", finiteOrNull(report.roi_coverage.median)},
              {"roi_coverage_mean", finiteOrNull(report.roi_coverage.mean)}};
    if (report.evaluation) {
      const auto& ev = *report.evaluation;
      json["gate_m"] = finiteOrNull(ev.gate());
      const auto counts = [](const eval::DetectionCounts& c) {
        return Json{{"truths", c.truths},           {"found", c.truths_found},
                    {"recall", finiteOrNull(c.recall())}, {"detections", c.detections},
                    {"right", c.detections_right},  {"precision", finiteOrNull(c.precision())},
                    {"visible", c.visible},         {"visible_recall", finiteOrNull(c.visibleRecall())}};
      };
      json["doors"] = counts(ev.doors());
      json["corners"] = counts(ev.corners());
      for (std::size_t k = 0; k < kNumFeatureTypes; ++k) {
        json[toString(static_cast<FeatureType>(k))] = counts(ev.byType()[k]);
      }
      json["position_error_median_m"] = finiteOrNull(report.position_error_m.median);
    }
    outputs.add(options_.report_dir + "/features.json", jsonText(json));
  }
  outputs.commit();
  return report;
}

std::string FeaturesApp::markdown(const FeaturesReport& r) {
  std::ostringstream os;
  os << "# Doors and corners: " << r.input << "\n\n";
  os << r.scans << " scans (" << r.beams_per_scan << " beams). Per scan, median: segmentation "
     << fixed(r.segment_us.median, 2) << " us, detection " << fixed(r.detect_us.median, 2) << " us (p99 "
     << fixed(r.detect_us.p99, 2) << " us).\n\n";
  os << "| type | detections |\n|---|---:|\n";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) {
    os << "| " << toString(static_cast<FeatureType>(k)) << " | " << r.detections[k] << " |\n";
  }
  if (r.images > 0) {
    os << "\nCamera: " << r.images << " images, " << r.images_with_rois << " with regions of interest, " << r.rois
       << " regions; share of the image they cover: median " << fixed(r.roi_coverage.median, 3) << ", mean "
       << fixed(r.roi_coverage.mean, 3) << ", max " << fixed(r.roi_coverage.max, 3) << ".\n";
  }
  if (!r.evaluation) return os.str();
  const auto& ev = *r.evaluation;
  os << "\n## Against the ground truth (match within " << fixed(ev.gate(), 2) << " m)\n\n";
  os << "Recall counts the resolvable true features (both walls of a corner, the walls beside a door and "
        "the doorway seen with enough beams); precision counts a detection right when it matches any true "
        "feature in view of its type. \"Recall, all in view\" also counts the unresolvable ones.\n\n";
  os << "| kind | true (resolvable) | found | recall | detections | right | precision | in view | recall, all in view |\n";
  os << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& name, const eval::DetectionCounts& c) {
    os << "| " << name << " | " << c.truths << " | " << c.truths_found << " | " << fixed(c.recall(), 3) << " | "
       << c.detections << " | " << c.detections_right << " | " << fixed(c.precision(), 3) << " | " << c.visible
       << " | " << fixed(c.visibleRecall(), 3) << " |\n";
  };
  row("**doors (any type)**", ev.doors());
  for (std::size_t k = 0; k < 3; ++k) row(toString(static_cast<FeatureType>(k)), ev.byType()[k]);
  row("**corners (either)**", ev.corners());
  for (std::size_t k = 3; k < kNumFeatureTypes; ++k) row(toString(static_cast<FeatureType>(k)), ev.byType()[k]);
  os << "\nPosition error of matched features: median " << fixed(r.position_error_m.median, 3) << " m, p99 "
     << fixed(r.position_error_m.p99, 3) << " m.\n\n";
  os << "Confusion (rows: true type as the scan can show it; columns: detected type):\n\n| |";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) os << ' ' << toString(static_cast<FeatureType>(k)) << " |";
  os << "\n|---|";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) os << "---:|";
  os << '\n';
  for (std::size_t t = 0; t < kNumFeatureTypes; ++t) {
    os << "| " << toString(static_cast<FeatureType>(t)) << " |";
    for (std::size_t d = 0; d < kNumFeatureTypes; ++d) os << ' ' << ev.confusion()[t][d] << " |";
    os << '\n';
  }
  return os.str();
}

void FeaturesApp::print(const FeaturesReport& report, std::ostream& os) {
  os << markdown(report);
  if (!report.skipped.empty()) {
    os << "\nSkipped (" << report.skipped.size() << "):\n";
    for (std::size_t i = 0; i < std::min<std::size_t>(report.skipped.size(), 20); ++i) {
      os << "  " << report.skipped[i] << '\n';
    }
  }
}

}  // namespace lidarseg::apps
