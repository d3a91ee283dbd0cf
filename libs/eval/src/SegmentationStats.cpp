#include "lidarseg/eval/SegmentationStats.h"

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "lidarseg/core/Angles.h"

namespace lidarseg::eval {

namespace {

// The level's summary; `valid_beams`: the valid beams of every scan, for the coverage.
template <typename Accumulator>
LevelStats summariseLevel(const Accumulator& a, double valid_beams) {
  LevelStats out;
  out.segments_per_scan = summarize(a.counts);
  out.segment_length_m = summarize(a.lengths);
  out.point_coverage = valid_beams > 0.0 ? a.points / valid_beams : 0.0;
  out.mean_rms_residual_m =
      a.lengths.empty() ? 0.0 : a.residual_sum / static_cast<double>(a.lengths.size());
  out.median_theta_sigma_rad = summarize(a.theta_sigmas).median;
  out.segments_without_direction = a.without_direction;
  return out;
}

// The segments left out of sigma theta, per level, when there are any.
void printSegmentsWithoutDirection(const SegmentStatsReport& r, std::ostream& os) {
  std::ostringstream counts;
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    if (r.levels[l].segments_without_direction == 0) continue;
    counts << (counts.tellp() > 0 ? ", " : "") << "level " << l << ": " << r.levels[l].segments_without_direction;
  }
  if (counts.tellp() <= 0) return;
  os << "  segments of points at one place (no direction, left out of sigma theta): " << counts.str() << "\n";
}

}  // namespace

void SegmentationStats::add(const Segmentation& seg, double wall_danielsson_us, double cascade_us) {
  t_wd_.push_back(wall_danielsson_us);
  t_cascade_.push_back(cascade_us);
  t_total_.push_back(wall_danielsson_us + cascade_us);
  valid_beams_.push_back(static_cast<double>(seg.num_valid_beams));
  total_valid_ += static_cast<double>(seg.num_valid_beams);
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    const SegmentLevel& level = seg.levels[l];
    if (l > 0 && level.segments.size() > seg.levels[l - 1].segments.size()) never_gain_ = false;
    LevelAccumulator& a = acc_[l];
    a.counts.push_back(static_cast<double>(level.segments.size()));
    for (const Segment& s : level.segments) {
      a.lengths.push_back(s.length_m);
      a.points += s.num_points;
      a.residual_sum += s.rms_residual_m;
      // A segment of points at one place has no direction (fitSegment(): infinite
      // covariance): it has no θ noise to summarise, and is counted instead.
      if (std::isfinite(s.covariance(1, 1))) {
        a.theta_sigmas.push_back(std::sqrt(s.covariance(1, 1)));
      } else {
        ++a.without_direction;
      }
    }
  }
}

void SegmentationStats::summarise(SegmentStatsReport& report) const {
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l)
    report.levels[l] = summariseLevel(acc_[l], total_valid_);
  report.valid_beams_per_scan = summarize(valid_beams_);
  report.wall_danielsson_us = summarize(t_wd_);
  report.cascade_us = summarize(t_cascade_);
  report.total_us = summarize(t_total_);
  report.levels_never_gain_segments = report.levels_never_gain_segments && never_gain_;
}

void printSegmentStats(const SegmentStatsReport& r, std::ostream& os) {
  const auto flags = os.flags();
  os << std::fixed;
  os << "lidarseg-segment: " << r.input << "\n";
  os << "  scans: " << r.scans << " (sensor "
     << (r.sensor_label.empty() ? std::string("without a label") : "'" + r.sensor_label + "'")
     << ", " << r.beams_per_scan << " beams over " << std::setprecision(1) << r.field_of_view_deg
     << " deg, max range " << r.max_range_m << " m; " << std::setprecision(0)
     << r.valid_beams_per_scan.mean << " valid beams per scan on average)\n";
  os << "\n  level              segments per scan           segment length (m)      "
        "points in   rms resid.  sigma theta\n";
  os << "                     mean  median   min   max     mean  median    max     "
        "segments   (mm)        median (deg)\n";
  for (std::size_t l = 0; l < kNumCascadeLevels; ++l) {
    const LevelStats& s = r.levels[l];
    os << "  " << l << " " << std::left << std::setw(16) << toString(static_cast<CascadeLevel>(l))
       << std::right << std::setprecision(1) << std::setw(6) << s.segments_per_scan.mean
       << std::setw(8) << s.segments_per_scan.median << std::setprecision(0) << std::setw(6)
       << s.segments_per_scan.min << std::setw(6) << s.segments_per_scan.max << std::setprecision(2)
       << std::setw(9) << s.segment_length_m.mean << std::setw(8) << s.segment_length_m.median
       << std::setw(7) << s.segment_length_m.max << std::setprecision(1) << std::setw(10)
       << 100.0 * s.point_coverage << " %" << std::setw(9) << 1000.0 * s.mean_rms_residual_m
       << std::setprecision(3) << std::setw(13);
    if (s.segments_without_direction > 0 && s.segments_without_direction == s.segment_length_m.count) {
      os << "n/a\n";  // no segment with a direction: no θ noise at all
    } else {
      os << s.median_theta_sigma_rad * kRadToDeg << "\n";
    }
  }
  printSegmentsWithoutDirection(r, os);
  os << "\n  time per scan (us, this run)      median     p99      max\n";
  const auto timeRow = [&](const char* name, const Summary& t) {
    os << "    " << std::left << std::setw(30) << name << std::right << std::setprecision(2)
       << std::setw(8) << t.median << std::setw(9) << t.p99 << std::setw(9) << t.max << "\n";
  };
  timeRow("Wall-Danielsson", r.wall_danielsson_us);
  timeRow("cascade filter", r.cascade_us);
  timeRow("segmentation total", r.total_us);
  os << "\n  levels never gain segments: " << (r.levels_never_gain_segments ? "yes" : "NO") << "\n";
  os.flags(flags);
}

}  // namespace lidarseg::eval
