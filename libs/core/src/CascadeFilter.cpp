#include "lidarseg/core/CascadeFilter.h"

#include <algorithm>
#include <cmath>

#include "Validation.h"

namespace lidarseg {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Appends `next` (the following segment in scan order) to `into` and re-fits it from the
// union of the points.
void absorb(Segment& into, const Segment& next, const SensorNoise& noise) {
  into.moments += next.moments;
  into.num_points += next.num_points;
  into.last_beam = next.last_beam;
  into.last_point = next.last_point;
  into.parts_end = next.parts_end;
  fitSegment(into, noise);
}
}  // namespace

void FusionParams::validate(const std::string& key_prefix) const {
  detail::requireInRange(key_prefix + "max_angle_rad", max_angle_rad, 0.0, 0.5 * kPi);
  detail::requireNonNegative(key_prefix + "max_line_distance_m", max_line_distance_m);
  detail::requireNonNegative(key_prefix + "max_gap_m", max_gap_m);
  detail::requireNonNegative(key_prefix + "noise_gate_sigmas", noise_gate_sigmas);
}

void ErosionParams::validate() const {
  detail::requireNonNegative("erosion_min_length_m", min_length_m);
}

void CascadeParams::validate() const {
  first_fusion.validate("fusion1_");
  erosion.validate();
  second_fusion.validate("fusion2_");
}

CascadeFilter::CascadeFilter(const CascadeParams& params, const SensorNoise& noise)
    : params_(params), noise_(noise) {
  params_.validate();
  noise_.validate();
}

bool CascadeFilter::canFuse(const Segment& a, const Segment& b, const FusionParams& p,
                            const SensorNoise& noise) {
  // Close (D): the end of a and the start of b.
  if ((b.start - a.end).squaredNorm() > p.max_gap_m * p.max_gap_m) return false;
  // Parallel: line directions compared modulo pi (normals may point either way).
  const double angle = std::abs(std::remainder(a.theta_rad - b.theta_rad, kPi));
  // Aligned (d): the shorter segment's endpoints against the longer, better-known line.
  const Segment& longer = a.length_m >= b.length_m ? a : b;
  const Segment& shorter = a.length_m >= b.length_m ? b : a;
  if (angle <= p.max_angle_rad &&
      std::abs(longer.signedDistance(shorter.start)) <= p.max_line_distance_m &&
      std::abs(longer.signedDistance(shorter.end)) <= p.max_line_distance_m) {
    return true;
  }
  // Noise gate: does one line explain both within the noise?
  if (p.noise_gate_sigmas <= 0.0) return false;
  LineMoments both = a.moments;
  both += b.moments;
  const double rise = residualSumOfSquares(both) - residualSumOfSquares(a.moments) -
                      residualSumOfSquares(b.moments);
  const double limit = p.noise_gate_sigmas * noise.range_sigma_m;
  return rise <= limit * limit;
}

void CascadeFilter::fuse(const SegmentLevel& in, SegmentLevel& out, const FusionParams& params,
                         bool wraps_around) const {
  out.segments.clear();
  out.parts.assign(in.parts.begin(), in.parts.end());
  if (in.segments.empty()) return;

  // Fusing consecutive segments keeps each segment's parts contiguous in `parts`.
  Segment current = in.segments.front();
  for (std::size_t j = 1; j < in.segments.size(); ++j) {
    const Segment& next = in.segments[j];
    if (canFuse(current, next, params, noise_)) {
      absorb(current, next, noise_);
    } else {
      out.segments.push_back(current);
      current = next;
    }
  }
  out.segments.push_back(current);

  // A full-turn scan: a wall crossing the wrap-around is split between the last and the
  // first segments.
  if (!wraps_around || out.segments.size() < 2) return;
  if (!canFuse(out.segments.back(), out.segments.front(), params, noise_)) return;
  const Segment head = out.segments.front();
  const std::uint32_t shift = head.parts_end - head.parts_begin;  // head.parts_begin == 0
  // Move the head's parts to the end so that the merged segment's parts stay contiguous.
  std::rotate(out.parts.begin(), out.parts.begin() + shift, out.parts.end());
  out.segments.erase(out.segments.begin());
  for (Segment& s : out.segments) {
    s.parts_begin -= shift;
    s.parts_end -= shift;
  }
  Segment moved_head = head;
  moved_head.parts_end = static_cast<std::uint32_t>(out.parts.size());
  absorb(out.segments.back(), moved_head, noise_);
}

void CascadeFilter::erode(const SegmentLevel& in, SegmentLevel& out) const {
  out.clear();
  for (const Segment& s : in.segments) {
    if (s.length_m < params_.erosion.min_length_m || s.num_points < params_.erosion.min_points) {
      continue;
    }
    Segment kept = s;
    kept.parts_begin = static_cast<std::uint32_t>(out.parts.size());
    out.parts.insert(out.parts.end(), in.parts.begin() + s.parts_begin,
                     in.parts.begin() + s.parts_end);
    kept.parts_end = static_cast<std::uint32_t>(out.parts.size());
    out.segments.push_back(kept);
  }
}

void CascadeFilter::apply(Segmentation& seg) const {
  auto& lv = seg.levels;
  fuse(lv[0], lv[1], params_.first_fusion, seg.wraps_around);
  erode(lv[1], lv[2]);
  fuse(lv[2], lv[3], params_.second_fusion, seg.wraps_around);
}

}  // namespace lidarseg
