#include "lidarseg/report/FeaturesReport.h"

#include <sstream>

#include "lidarseg/report/Format.h"
#include "lidarseg/report/JsonText.h"
#include "lidarseg/report/RecordGate.h"

namespace lidarseg::report {

namespace {

// The name of feature type number k.
const char* typeName(std::size_t k) { return toString(static_cast<FeatureType>(k)); }

// Truths found and detections right of one kind of feature, for features.json.
Json countsJson(const eval::DetectionCounts& c) {
  return Json{{"truths", c.truths},
              {"found", c.truths_found},
              {"recall", finiteOrNull(c.recall())},
              {"detections", c.detections},
              {"right", c.detections_right},
              {"precision", finiteOrNull(c.precision())},
              {"visible", c.visible},
              {"visible_recall", finiteOrNull(c.visibleRecall())}};
}

// features.json: counts and median times, and the scores when a ground truth was given.
Json reportJson(const FeaturesReport& report) {
  Json json{{"input", report.input},
            {"scans", report.scans},
            {"detect_us_median", finiteOrNull(report.detect_us.median)},
            {"segment_us_median", finiteOrNull(report.segment_us.median)},
            {"images", report.images},
            {"images_with_rois", report.images_with_rois},
            {"rois", report.rois},
            {"roi_coverage_median", finiteOrNull(report.roi_coverage.median)},
            {"roi_coverage_mean", finiteOrNull(report.roi_coverage.mean)},
            {"skipped", report.skipped_count},
            {"skipped_examples", report.skipped},
            {"non_increasing_stamps", report.stamps.non_increasing_stamps},
            {"time_gaps", report.stamps.time_gaps},
            {"clock_jumps", report.stamps.clock_jumps},
            {"warnings", report.log_warnings},
            {"warning_kinds", warningKindsJson(report.log_warning_kinds)}};
  if (!report.evaluation) return json;
  const auto& ev = *report.evaluation;
  json["gate_m"] = finiteOrNull(ev.gate());
  json["doors"] = countsJson(ev.doors());
  json["corners"] = countsJson(ev.corners());
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) json[typeName(k)] = countsJson(ev.byType()[k]);
  json["position_error_median_m"] = finiteOrNull(report.position_error_m.median);
  return json;
}

}  // namespace

std::string featuresMarkdown(const FeaturesReport& r) {
  std::ostringstream os;
  os << "# Doors and corners: " << r.input << "\n\n";
  os << r.scans << " scans (" << r.beams_per_scan << " beams). Per scan, median: segmentation "
     << fixed(r.segment_us.median, 2) << " us, detection " << fixed(r.detect_us.median, 2)
     << " us (p99 " << fixed(r.detect_us.p99, 2) << " us).\n\n";
  os << "Log: " << recordCountsLine(r.skipped_count, r.stamps) << ".\n\n";
  os << "| type | detections |\n|---|---:|\n";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) {
    os << "| " << typeName(k) << " | " << r.detections[k] << " |\n";
  }
  if (r.images > 0) {
    os << "\nCamera: " << r.images << " images, " << r.images_with_rois
       << " with regions of interest, " << r.rois
       << " regions; share of the image they cover: median " << fixed(r.roi_coverage.median, 3)
       << ", mean " << fixed(r.roi_coverage.mean, 3) << ", max " << fixed(r.roi_coverage.max, 3)
       << ".\n";
  }
  if (!r.evaluation) return os.str();
  const auto& ev = *r.evaluation;
  os << "\n## Against the ground truth (match within " << fixed(ev.gate(), 2) << " m)\n\n";
  os << "Recall counts the resolvable true features (both walls of a corner, the walls beside a "
        "door and "
        "the doorway seen with enough beams); precision counts a detection right when it matches "
        "any true "
        "feature in view of its type. \"Recall, all in view\" also counts the unresolvable "
        "ones.\n\n";
  os << "| kind | true (resolvable) | found | recall | detections | right | precision | in view | "
        "recall, all in view |\n";
  os << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& name, const eval::DetectionCounts& c) {
    os << "| " << name << " | " << c.truths << " | " << c.truths_found << " | "
       << fixed(c.recall(), 3) << " | " << c.detections << " | " << c.detections_right << " | "
       << fixed(c.precision(), 3) << " | " << c.visible << " | " << fixed(c.visibleRecall(), 3)
       << " |\n";
  };
  row("**doors (any type)**", ev.doors());
  for (std::size_t k = 0; k < 3; ++k) row(typeName(k), ev.byType()[k]);
  row("**corners (either)**", ev.corners());
  for (std::size_t k = 3; k < kNumFeatureTypes; ++k) row(typeName(k), ev.byType()[k]);
  os << "\nPosition error of matched features: median " << fixed(r.position_error_m.median, 3)
     << " m, p99 " << fixed(r.position_error_m.p99, 3) << " m.\n\n";
  os << "Confusion (rows: true type as the scan can show it; columns: detected type):\n\n| |";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) os << ' ' << typeName(k) << " |";
  os << "\n|---|";
  for (std::size_t k = 0; k < kNumFeatureTypes; ++k) os << "---:|";
  os << '\n';
  for (std::size_t t = 0; t < kNumFeatureTypes; ++t) {
    os << "| " << typeName(t) << " |";
    for (std::size_t d = 0; d < kNumFeatureTypes; ++d) os << ' ' << ev.confusion()[t][d] << " |";
    os << '\n';
  }
  return os.str();
}

std::string featuresJson(const FeaturesReport& report) { return jsonText(reportJson(report)); }

}  // namespace lidarseg::report
