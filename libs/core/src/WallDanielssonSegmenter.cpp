#include "lidarseg/core/WallDanielssonSegmenter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Validation.h"

namespace lidarseg {

namespace {

// Moments of the points of beams [first, end) (all valid). A separate, branch-free loop so
// that the compiler can vectorise the sums; the bearing-only sums come from the layout.
void accumulateMoments(const Eigen::Vector2d* points, const double* ranges,
                       const BeamLayout& layout, std::size_t first, std::size_t end,
                       LineMoments& m) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0, sw = 0, swx = 0, swy = 0;
#pragma omp simd reduction(+ : sx, sy, sxx, sxy, syy, sw, swx, swy)
  for (std::size_t k = first; k < end; ++k) {
    const double x = points[k].x(), y = points[k].y();
    const double inv_r = 1.0 / ranges[k];
    const double w = inv_r * inv_r;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    sw += w;
    swx += w * x;
    swy += w * y;
  }
  m.count = static_cast<double>(end - first);
  m.sum_x = sx;
  m.sum_y = sy;
  m.sum_xx = sxx;
  m.sum_xy = sxy;
  m.sum_yy = syy;
  m.sum_w = sw;
  m.sum_wx = swx;
  m.sum_wy = swy;
  layout.sumOuterProducts(first, end - 1, m.sum_wxx, m.sum_wxy, m.sum_wyy);
}

// Points of all beams in the sensor frame, NaN for invalid beams; returns the number of
// valid beams. Branch-free per beam so that the compiler can vectorise it.
std::size_t toPoints(const Scan& scan, const BeamLayout& layout, const std::uint8_t* flags,
                     Eigen::Vector2d* points) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const double lo = std::max(scan.min_range_m, kMinPhysicalRangeM);
  const double hi = std::min(scan.max_range_m, kMaxPhysicalRangeM);
  const double* ranges = scan.ranges_m.data();
  std::size_t valid = 0;
  const std::size_t n = scan.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double r = ranges[i];
    // NaN fails both comparisons.
    const bool ok = (r > lo) & (r < hi) & (flags == nullptr || flags[i] != 0);
    valid += ok;
    points[i] = ok ? Eigen::Vector2d(r * layout.cosine(i), r * layout.sine(i))
                   : Eigen::Vector2d(kNaN, kNaN);
  }
  return valid;
}

}  // namespace

void WallDanielssonParams::validate() const {
  detail::requirePositive("wd_threshold_m", threshold_m);
  detail::requirePositive("wd_max_range_jump_m", max_range_jump_m);
  detail::requireNonNegative("wd_max_range_jump_ratio", max_range_jump_ratio);
  if (min_points < 2) detail::failKey("wd_min_points", ">= 2", static_cast<double>(min_points));
}

WallDanielssonSegmenter::WallDanielssonSegmenter(const WallDanielssonParams& params,
                                                 const SensorNoise& noise)
    : params_(params), noise_(noise) {
  params_.validate();
  noise_.validate();
}

void WallDanielssonSegmenter::segment(const Scan& scan, Segmentation& out) const {
  segment(scan, out, Twist2D{});
}

void WallDanielssonSegmenter::segment(const Scan& scan, Segmentation& out, const Twist2D& motion) const {
  scan.validate();
  out.clear();
  const std::size_t n = scan.size();
  const BeamLayout& layout = *scan.layout;
  out.wraps_around = layout.wrapsAround();

  out.points.resize(n);
  out.num_valid_beams = n == 0 ? 0
                               : (scan.valid.empty()
                                      ? toPoints(scan, layout, nullptr, out.points.data())
                                      : toPoints(scan, layout, scan.valid.data(), out.points.data()));
  const bool moving = motion.vx != 0.0 || motion.vy != 0.0 || motion.omega != 0.0;
  if (moving && !scan.time_offsets_s.empty()) {
    // p_0 = T_0_i p_i with T_0_i the motion during the beam's time offset; first order in
    // the small rotation (omega * 15 ms).
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Vector2d& p = out.points[i];
      if (std::isnan(p.x())) continue;
      const double t = scan.time_offsets_s[i];
      const double a = motion.omega * t;
      const double c = 1.0 - 0.5 * a * a;
      p = Eigen::Vector2d(c * p.x() - a * p.y() + motion.vx * t, a * p.x() + c * p.y() + motion.vy * t);
    }
  }

  SegmentLevel& level0 = out.levels[0];
  // |area| / chord > T  <=>  (2 area)^2 > 4 T^2 chord^2: no square root per point.
  const double limit = 4.0 * params_.threshold_m * params_.threshold_m;
  const double* ranges = scan.ranges_m.data();
  const Eigen::Vector2d* points = out.points.data();

  std::size_t i = 0;
  while (i < n) {
    if (std::isnan(points[i].x())) {
      ++i;
      continue;
    }
    const std::size_t first = i;
    const Eigen::Vector2d p0 = points[first];
    double twice_area = 0.0;  // signed, of the polygon p0..pk closed by the chord
    double prev_qx = 0.0, prev_qy = 0.0;
    double prev_r = ranges[first];

    std::size_t k = first + 1;
    for (; k < n; ++k) {
      const Eigen::Vector2d& p = points[k];
      if (std::isnan(p.x())) break;
      const double r = ranges[k];
      const double jump_limit =
          std::max(params_.max_range_jump_m, params_.max_range_jump_ratio * std::min(r, prev_r));
      if (std::abs(r - prev_r) > jump_limit) break;
      const double qx = p.x() - p0.x();
      const double qy = p.y() - p0.y();
      twice_area += prev_qx * qy - prev_qy * qx;
      if (twice_area * twice_area > limit * (qx * qx + qy * qy)) break;
      prev_qx = qx;
      prev_qy = qy;
      prev_r = r;
    }
    // No back-stepping (paper II.A): the point that broke the test starts the next segment.
    if (k - first >= params_.min_points) {
      const auto index = static_cast<std::uint32_t>(level0.segments.size());
      Segment& seg = level0.segments.emplace_back();
      seg.first_beam = static_cast<std::uint32_t>(first);
      seg.last_beam = static_cast<std::uint32_t>(k - 1);
      seg.num_points = static_cast<std::uint32_t>(k - first);
      seg.parts_begin = index;
      seg.parts_end = index + 1;
      seg.first_point = p0;
      seg.last_point = points[k - 1];
      accumulateMoments(points, ranges, layout, first, k, seg.moments);
      fitSegment(seg, noise_);
      level0.parts.push_back(index);
    }
    i = k;
  }
}

}  // namespace lidarseg
