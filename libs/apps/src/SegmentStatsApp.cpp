#include "lidarseg/apps/SegmentStatsApp.h"
#include "lidarseg/core/Angles.h"

#include "OutputFiles.h"
#include "Timing.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "lidarseg/mrpt/LaserLogReader.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SegmentationConfig.h"

namespace lidarseg::apps {

namespace {


struct LevelAccumulator {
  std::vector<double> counts;
  std::vector<double> lengths;
  std::vector<double> theta_sigmas;
  double points = 0.0;
  double residual_sum = 0.0;
};

}  // namespace

SegmentStatsApp::SegmentStatsApp(SegmentStatsOptions options) : options_(std::move(options)) {}

SegmentStatsReport SegmentStatsApp::run() {
  SegmentationParams params;
  if (!options_.config_path.empty()) {
    // The shared configuration (every section optional), or a section of the user's choice.
    params = options_.section == mrpt_adapter::kSegmentationSection
                 ? mrpt_adapter::LidarsegConfig::loadFile(options_.config_path).odometry.segmentation
                 : mrpt_adapter::loadSegmentationParamsFile(options_.config_path, options_.section);
  }
  const ScanSegmenter segmenter(params);
  mrpt_adapter::LaserLogReader reader(options_.input, options_.sensor_label);
  mrpt_adapter::ScanConverter converter;

  SegmentStatsReport report;
  report.input = options_.input;
  std::array<LevelAccumulator, kNumCascadeLevels> acc;
  std::vector<double> t_wd, t_cascade, t_total, valid_beams;
  double total_valid = 0.0;
  std::ostringstream csv;
  csv << "scan,stamp_s,valid_beams,level0,level1,level2,level3,wd_us,cascade_us\n";
  csv << std::setprecision(12);

  Segmentation seg;
  while (auto item = reader.next()) {
    if (options_.max_scans > 0 && report.scans + report.skipped.size() >= options_.max_scans) {
      break;
    }
    const auto& obs = *item->observation;
    Scan scan;
    double wd_us = 0.0, cascade_us = 0.0;
    try {
      scan = converter.convert(obs);
      const auto t0 = Clock::now();
      segmenter.wallDanielsson().segment(scan, seg);
      wd_us = microsecondsSince(t0);
      const auto t1 = Clock::now();
      segmenter.cascade().apply(seg);
      cascade_us = microsecondsSince(t1);
    } catch (const std::exception& e) {
      report.skipped.push_back(item->where + " (scan " + std::to_string(item->index) + "): " + e.what());
      continue;
    }
    if (report.scans == 0) {
      report.beams_per_scan = scan.size();
      report.field_of_view_deg = static_cast<double>(obs.aperture) * kRadToDeg;
      report.max_range_m = scan.max_range_m;
    }
    ++report.scans;
    t_wd.push_back(wd_us);
    t_cascade.push_back(cascade_us);
    t_total.push_back(wd_us + cascade_us);
    valid_beams.push_back(static_cast<double>(seg.num_valid_beams));
    total_valid += static_cast<double>(seg.num_valid_beams);

    for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
      const SegmentLevel& level = seg.levels[l];
      if (l > 0 && level.segments.size() > seg.levels[l - 1].segments.size()) {
        report.levels_never_gain_segments = false;
      }
      LevelAccumulator& a = acc[l];
      a.counts.push_back(static_cast<double>(level.segments.size()));
      for (const Segment& s : level.segments) {
        a.lengths.push_back(s.length_m);
        a.points += s.num_points;
        a.residual_sum += s.rms_residual_m;
        a.theta_sigmas.push_back(std::sqrt(s.covariance(1, 1)));
      }
    }
    csv << item->index << ',' << scan.stamp_s << ',' << seg.num_valid_beams;
    for (const auto& level : seg.levels) csv << ',' << level.segments.size();
    csv << ',' << wd_us << ',' << cascade_us << '\n';
  }
  report.sensor_label = reader.sensor();
  for (const auto& issue : reader.issues()) report.skipped.push_back(issue);
  if (report.scans == 0 && report.skipped.empty()) {
    throw std::runtime_error("'" + options_.input + "' holds no 2D laser scan" +
                             (options_.sensor_label.empty()
                                  ? std::string()
                                  : " with sensor label '" + options_.sensor_label + "'"));
  }

  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    LevelStats& out = report.levels[l];
    LevelAccumulator& a = acc[l];
    out.segments_per_scan = summarize(a.counts);
    out.segment_length_m = summarize(a.lengths);
    out.point_coverage = total_valid > 0.0 ? a.points / total_valid : 0.0;
    out.mean_rms_residual_m = a.lengths.empty() ? 0.0 : a.residual_sum / static_cast<double>(a.lengths.size());
    out.median_theta_sigma_rad = summarize(a.theta_sigmas).median;
  }
  report.valid_beams_per_scan = summarize(valid_beams);
  report.wall_danielsson_us = summarize(t_wd);
  report.cascade_us = summarize(t_cascade);
  report.total_us = summarize(t_total);

  if (!options_.csv_path.empty()) writeFileAtomically(options_.csv_path, csv.str());
  return report;
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
  if (!r.skipped.empty()) {
    os << "  skipped scans: " << r.skipped.size() << "\n";
    for (const auto& s : r.skipped) os << "    " << s << "\n";
  }
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
