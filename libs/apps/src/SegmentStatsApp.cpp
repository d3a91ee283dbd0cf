#include "lidarseg/apps/SegmentStatsApp.h"
#include "lidarseg/core/Angles.h"

#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/pipeline/Progress.h"
#include "lidarseg/pipeline/Timing.h"

#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/SegmentationConfig.h"

namespace lidarseg::apps {

using pipeline::OutputSet;

using pipeline::Clock;
using pipeline::Progress;
using pipeline::microsecondsSince;

namespace {

// The [segmentation] section of the shared configuration (every section optional), or a
// section of the user's choice read alone; the defaults without a file.
SegmentationParams loadParams(const SegmentStatsOptions& options) {
  if (options.config_path.empty()) return {};
  return options.section == mrpt_adapter::kSegmentationSection
             ? mrpt_adapter::LidarsegConfig::loadFile(options.config_path).odometry.segmentation
             : mrpt_adapter::loadSegmentationParamsFile(options.config_path, options.section);
}

// Every scan segmented and cascaded (timed), its levels accumulated and its CSV row written.
class ScanPass {
 public:
  // Throws for invalid parameters.
  ScanPass(const SegmentationParams& params, SegmentStatsReport& report) : segmenter_(params), report_(report) {
    csv_ << "scan,stamp_s,valid_beams,level0,level1,level2,level3,wd_us,cascade_us\n";
    csv_ << std::setprecision(12);
  }

  // The record's scan; listed as skipped when it cannot be converted or segmented.
  void addScan(const mrpt_adapter::LaserRecord& record) {
    const Scan& scan = record.scan;
    double wd_us = 0.0, cascade_us = 0.0;
    try {
      const auto t0 = Clock::now();
      segmenter_.wallDanielsson().segment(scan, seg_);
      wd_us = microsecondsSince(t0);
      const auto t1 = Clock::now();
      segmenter_.cascade().apply(seg_);
      cascade_us = microsecondsSince(t1);
    } catch (const std::exception& e) {
      report_.skipped.push_back(record.where + " (scan " + std::to_string(record.index) + "): " + e.what());
      return;
    }
    if (report_.scans == 0) {
      report_.beams_per_scan = scan.size();
      report_.field_of_view_deg = static_cast<double>(record.observation->aperture) * kRadToDeg;
      report_.max_range_m = scan.max_range_m;
    }
    ++report_.scans;
    stats_.add(seg_, wd_us, cascade_us);
    csv_ << record.index << ',' << scan.stamp_s << ',' << seg_.num_valid_beams;
    for (const auto& level : seg_.levels) csv_ << ',' << level.segments.size();
    csv_ << ',' << wd_us << ',' << cascade_us << '\n';
  }

  // The per-scan samples summarised into the report.
  void summarise() { stats_.summarise(report_); }

  // The per-scan CSV, header included.
  std::string csv() const { return csv_.str(); }

 private:
  const ScanSegmenter segmenter_;
  SegmentStatsReport& report_;
  Segmentation seg_;
  eval::SegmentationStats stats_;
  std::ostringstream csv_;
};

}  // namespace

SegmentStatsApp::SegmentStatsApp(SegmentStatsOptions options) : options_(std::move(options)) {}

namespace {

// Every scan of the log through the pass (up to max_scans, skipped ones counted), with
// progress on stderr; the sensor and what the reader skipped go into the report.
void readLog(const SegmentStatsOptions& o, ScanPass& pass, SegmentStatsReport& report) {
  mrpt_adapter::LaserLogReader reader(o.input, o.sensor_label);
  Progress progress("lidarseg-segment", o.progress, o.max_scans);
  while (auto record = reader.next()) {
    if (o.max_scans > 0 && report.scans + report.skipped.size() >= o.max_scans) break;
    pass.addScan(*record);
    progress.update(report.scans, reader.fractionRead());
  }
  progress.done(report.scans);
  report.sensor_label = reader.sensor();
  for (const auto& issue : reader.issues()) report.skipped.push_back(issue);
  if (report.scans == 0 && report.skipped.empty()) {
    throw std::runtime_error("'" + o.input + "' holds no 2D laser scan" +
                             (o.sensor_label.empty() ? std::string() : " with sensor label '" + o.sensor_label + "'"));
  }
}

}  // namespace

SegmentStatsReport SegmentStatsApp::run() {
  // Before any work: an output that is an input is refused, a second writer at once.
  OutputSet outputs;
  outputs.claimOutputs({{options_.csv_path, "--csv"}}, {}, {options_.input, options_.config_path});
  SegmentStatsReport report;
  report.input = options_.input;
  ScanPass pass(loadParams(options_), report);
  readLog(options_, pass, report);
  pass.summarise();
  if (!options_.csv_path.empty()) outputs.add(options_.csv_path, pass.csv());
  outputs.commit();
  return report;
}

void SegmentStatsApp::printWarnings(const SegmentStatsReport& r, std::ostream& err) {
  if (r.skipped.empty()) return;
  err << "lidarseg-segment: warning: " << r.skipped.size() << " scans skipped, the first: " << r.skipped.front()
      << "\n";
}

}  // namespace lidarseg::apps
