#include "lidarseg/apps/SegmentStatsApp.h"
#include "lidarseg/core/Angles.h"

#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/pipeline/Progress.h"
#include "lidarseg/pipeline/Timing.h"

#include <cmath>
#include <iomanip>
#include <ostream>
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

// One level's samples over the log, summarised at the end.
struct LevelAccumulator {
  std::vector<double> counts;
  std::vector<double> lengths;
  std::vector<double> theta_sigmas;
  double points = 0.0;
  double residual_sum = 0.0;
};

// The [segmentation] section of the shared configuration (every section optional), or a
// section of the user's choice read alone; the defaults without a file.
SegmentationParams loadParams(const SegmentStatsOptions& options) {
  if (options.config_path.empty()) return {};
  return options.section == mrpt_adapter::kSegmentationSection
             ? mrpt_adapter::LidarsegConfig::loadFile(options.config_path).odometry.segmentation
             : mrpt_adapter::loadSegmentationParamsFile(options.config_path, options.section);
}

// The level's summary; `valid_beams`: the valid beams of every scan, for the coverage.
LevelStats summariseLevel(const LevelAccumulator& a, double valid_beams) {
  LevelStats out;
  out.segments_per_scan = summarize(a.counts);
  out.segment_length_m = summarize(a.lengths);
  out.point_coverage = valid_beams > 0.0 ? a.points / valid_beams : 0.0;
  out.mean_rms_residual_m = a.lengths.empty() ? 0.0 : a.residual_sum / static_cast<double>(a.lengths.size());
  out.median_theta_sigma_rad = summarize(a.theta_sigmas).median;
  return out;
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
    t_wd_.push_back(wd_us);
    t_cascade_.push_back(cascade_us);
    t_total_.push_back(wd_us + cascade_us);
    valid_beams_.push_back(static_cast<double>(seg_.num_valid_beams));
    total_valid_ += static_cast<double>(seg_.num_valid_beams);
    addLevels();
    csv_ << record.index << ',' << scan.stamp_s << ',' << seg_.num_valid_beams;
    for (const auto& level : seg_.levels) csv_ << ',' << level.segments.size();
    csv_ << ',' << wd_us << ',' << cascade_us << '\n';
  }

  // The per-scan samples summarised into the report.
  void summarise() {
    for (std::size_t l = 0; l < kNumCascadeLevels; ++l) report_.levels[l] = summariseLevel(acc_[l], total_valid_);
    report_.valid_beams_per_scan = summarize(valid_beams_);
    report_.wall_danielsson_us = summarize(t_wd_);
    report_.cascade_us = summarize(t_cascade_);
    report_.total_us = summarize(t_total_);
  }

  // The per-scan CSV, header included.
  std::string csv() const { return csv_.str(); }

 private:
  // Each level's segments of this scan into its accumulator; notes a level that gains segments.
  void addLevels() {
    for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
      const SegmentLevel& level = seg_.levels[l];
      if (l > 0 && level.segments.size() > seg_.levels[l - 1].segments.size()) {
        report_.levels_never_gain_segments = false;
      }
      LevelAccumulator& a = acc_[l];
      a.counts.push_back(static_cast<double>(level.segments.size()));
      for (const Segment& s : level.segments) {
        a.lengths.push_back(s.length_m);
        a.points += s.num_points;
        a.residual_sum += s.rms_residual_m;
        a.theta_sigmas.push_back(std::sqrt(s.covariance(1, 1)));
      }
    }
  }

  const ScanSegmenter segmenter_;
  SegmentStatsReport& report_;
  Segmentation seg_;
  std::array<LevelAccumulator, kNumCascadeLevels> acc_;
  std::vector<double> t_wd_, t_cascade_, t_total_, valid_beams_;
  double total_valid_ = 0.0;
  std::ostringstream csv_;
};

}  // namespace

SegmentStatsApp::SegmentStatsApp(SegmentStatsOptions options) : options_(std::move(options)) {}

SegmentStatsReport SegmentStatsApp::run() {
  // Before any work: an output that is an input is refused, a second writer at once.
  OutputSet outputs;
  outputs.claimOutputs({{options_.csv_path, "--csv"}}, {}, {options_.input, options_.config_path});
  SegmentStatsReport report;
  report.input = options_.input;
  ScanPass pass(loadParams(options_), report);
  mrpt_adapter::LaserLogReader reader(options_.input, options_.sensor_label);
  Progress progress("lidarseg-segment", options_.progress, options_.max_scans);
  while (auto record = reader.next()) {
    if (options_.max_scans > 0 && report.scans + report.skipped.size() >= options_.max_scans) break;
    pass.addScan(*record);
    progress.update(report.scans, reader.fractionRead());
  }
  progress.done(report.scans);
  report.sensor_label = reader.sensor();
  for (const auto& issue : reader.issues()) report.skipped.push_back(issue);
  if (report.scans == 0 && report.skipped.empty()) {
    throw std::runtime_error("'" + options_.input + "' holds no 2D laser scan" +
                             (options_.sensor_label.empty()
                                  ? std::string()
                                  : " with sensor label '" + options_.sensor_label + "'"));
  }
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

void SegmentStatsApp::print(const SegmentStatsReport& r, std::ostream& os) {
  const auto flags = os.flags();
  os << std::fixed;
  os << "lidarseg-segment: " << r.input << "\n";
  os << "  scans: " << r.scans << " (sensor "
     << (r.sensor_label.empty() ? std::string("without a label") : "'" + r.sensor_label + "'")
     << ", " << r.beams_per_scan
     << " beams over " << std::setprecision(1) << r.field_of_view_deg << " deg, max range "
     << r.max_range_m << " m; " << std::setprecision(0) << r.valid_beams_per_scan.mean
     << " valid beams per scan on average)\n";
  os << "\n  level              segments per scan           segment length (m)      "
        "points in   rms resid.  sigma theta\n";
  os << "                     mean  median   min   max     mean  median    max     "
        "segments   (mm)        median (deg)\n";
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    const LevelStats& s = r.levels[l];
    os << "  " << l << " " << std::left << std::setw(16) << toString(static_cast<CascadeLevel>(l))
       << std::right << std::setprecision(1) << std::setw(6) << s.segments_per_scan.mean
       << std::setw(8) << s.segments_per_scan.median << std::setprecision(0) << std::setw(6)
       << s.segments_per_scan.min << std::setw(6) << s.segments_per_scan.max
       << std::setprecision(2) << std::setw(9) << s.segment_length_m.mean << std::setw(8)
       << s.segment_length_m.median << std::setw(7) << s.segment_length_m.max
       << std::setprecision(1) << std::setw(10) << 100.0 * s.point_coverage << " %"
       << std::setw(9) << 1000.0 * s.mean_rms_residual_m << std::setprecision(3)
       << std::setw(13) << s.median_theta_sigma_rad * kRadToDeg << "\n";
  }
  os << "\n  time per scan (us, this run)      median     p99      max\n";
  const auto timeRow = [&](const char* name, const Summary& t) {
    os << "    " << std::left << std::setw(30) << name << std::right << std::setprecision(2)
       << std::setw(8) << t.median << std::setw(9) << t.p99 << std::setw(9) << t.max << "\n";
  };
  timeRow("Wall-Danielsson", r.wall_danielsson_us);
  timeRow("cascade filter", r.cascade_us);
  timeRow("segmentation total", r.total_us);
  os << "\n  levels never gain segments: " << (r.levels_never_gain_segments ? "yes" : "NO")
     << "\n";
  os.flags(flags);
}

}  // namespace lidarseg::apps
