#include "lidarseg/apps/SegmentStatsApp.h"
#include "lidarseg/core/Angles.h"

#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/pipeline/ReadRecords.h"
#include "lidarseg/report/RecordGate.h"
#include "lidarseg/report/Timing.h"

#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/SegmentationConfig.h"

namespace lidarseg::apps {

using report::OutputSet;

using report::Clock;
using report::microsecondsSince;

namespace {

// The shared configuration (every section optional), or with a section of the user's
// choice read alone as [segmentation] (the other sections' defaults); the defaults
// without a file.
mrpt_adapter::LidarsegConfig loadConfig(const SegmentStatsOptions& options) {
  mrpt_adapter::LidarsegConfig config;
  if (options.config_path.empty()) {
    if (options.section != mrpt_adapter::kSegmentationSection) {  // it would be ignored (issue 16)
      throw std::invalid_argument("section '" + options.section + "' given without a parameter file");
    }
    return config;
  }
  if (options.section == mrpt_adapter::kSegmentationSection) {
    return mrpt_adapter::LidarsegConfig::loadFile(options.config_path);
  }
  config.odometry.segmentation = mrpt_adapter::loadSegmentationParamsFile(options.config_path, options.section);
  return config;
}

// Every scan segmented and cascaded (timed), its levels accumulated and its CSV row written.
class ScanPass {
 public:
  // Throws for invalid parameters.
  ScanPass(const SegmentationParams& params, SegmentStatsReport& report) : segmenter_(params), report_(report) {
    csv_ << "scan,stamp_s,valid_beams,level0,level1,level2,level3,wd_us,cascade_us\n";
    csv_ << std::setprecision(12);
  }

  // The record's scan at its run's stamp. @throws std::invalid_argument for a scan that
  // cannot be segmented (the gate skips it).
  void addScan(const mrpt_adapter::LaserRecord& record, const StampStep& time) {
    const Scan& scan = record.scan;
    const auto t0 = Clock::now();
    segmenter_.wallDanielsson().segment(scan, seg_);
    const double wd_us = microsecondsSince(t0);
    const auto t1 = Clock::now();
    segmenter_.cascade().apply(seg_);
    const double cascade_us = microsecondsSince(t1);
    if (report_.scans == 0) {
      report_.beams_per_scan = scan.size();
      report_.field_of_view_deg = static_cast<double>(mrpt_adapter::observationOf(record)->aperture) * kRadToDeg;
      report_.max_range_m = scan.max_range_m;
    }
    ++report_.scans;
    stats_.add(seg_, wd_us, cascade_us);
    csv_ << record.index << ',' << time.output_stamp_s << ',' << seg_.num_valid_beams;
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

// Every record of the log through the run's gate into the pass (up to max_scans scans),
// with progress on stderr; the sensor and what the gate and the reader skipped go into the
// report.
void readLog(const SegmentStatsOptions& o, const StampPolicyParams& stamps, ScanPass& pass, SegmentStatsReport& report) {
  mrpt_adapter::LaserLogReader reader(o.input, o.sensor_label);
  report::RecordGate gate(stamps);
  const auto use = [&](const mrpt_adapter::LaserRecord& record) {
    gate.pass(record, [&](const StampStep& time) { pass.addScan(record, time); });
  };
  pipeline::readRecords(reader, gate.counts(), {"lidarseg-segment", o.sensor_label, o.max_scans, o.progress}, use);
  report.sensor_label = reader.sensor();
  report::RecordCounts counts = gate.counts();
  pipeline::addReaderCounts(reader, counts);
  report.skipped = counts.skipped;
  report.skipped_count = counts.skipped_count;
  report.stamps = counts;
  report.warnings = counts.warnings;
  report.warning_kinds = counts.warning_kinds;
}

}  // namespace

SegmentStatsReport SegmentStatsApp::run() {
  // Before any work: an output that is an input is refused, a second writer at once.
  OutputSet outputs;
  outputs.claimOutputs({{options_.csv_path, "--csv"}}, {}, {options_.input, options_.config_path});
  SegmentStatsReport report;
  report.input = options_.input;
  const mrpt_adapter::LidarsegConfig config = loadConfig(options_);
  ScanPass pass(config.odometry.segmentation, report);
  readLog(options_, config.stamps, pass, report);
  pass.summarise();
  if (!options_.csv_path.empty()) outputs.add(options_.csv_path, pass.csv());
  outputs.commit();
  return report;
}

void SegmentStatsApp::print(const SegmentStatsReport& r, std::ostream& os) {
  eval::printSegmentStats(r, os);
  os << "  " << report::recordCountsLine(r.skipped_count, r.stamps) << "\n";
}

void SegmentStatsApp::printWarnings(const SegmentStatsReport& r, std::ostream& err) {
  report::printRecordWarnings(r.warning_kinds, "lidarseg-segment", err);
  if (r.skipped.empty()) return;
  err << "lidarseg-segment: warning: " << r.skipped_count << " scans or lines skipped, the first: " << r.skipped.front()
      << "\n";
}

}  // namespace lidarseg::apps
