#include "lidarseg/core/CascadeFilter.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>

#include "Validation.h"

namespace lidarseg {

namespace {

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

namespace {

// The fusion tests of FusionParams with their constants computed once per pass.
struct FusionGate {
  FusionGate(const FusionParams& p, const SensorNoise& noise)
      : max_gap_sq(p.max_gap_m * p.max_gap_m),
        sin_max_angle(std::sin(p.max_angle_rad)),
        max_line_distance(p.max_line_distance_m),
        max_rise(p.noise_gate_sigmas * noise.range_sigma_m * p.noise_gate_sigmas *
                 noise.range_sigma_m),
        noise_gate(p.noise_gate_sigmas > 0.0) {}

  bool operator()(const Segment& a, const Segment& b) const {
    // Close (D): the end of a and the start of b. Written so that NaN fails.
    if (!((b.start - a.end).squaredNorm() <= max_gap_sq)) return false;
    // Parallel: |sin| of the angle between the normals is the same modulo pi (normals may
    // point either way) and needs no trigonometry; max_angle_rad <= pi/2 keeps it monotonic.
    const double sin_angle = std::abs(a.normal.x() * b.normal.y() - a.normal.y() * b.normal.x());
    // Aligned (d): the shorter segment's endpoints against the longer, better-known line.
    const Segment& longer = a.length_m >= b.length_m ? a : b;
    const Segment& shorter = a.length_m >= b.length_m ? b : a;
    if (sin_angle <= sin_max_angle &&
        std::abs(longer.signedDistance(shorter.start)) <= max_line_distance &&
        std::abs(longer.signedDistance(shorter.end)) <= max_line_distance) {
      return true;
    }
    // Noise gate: does one line explain both within the noise?
    if (!noise_gate) return false;
    LineMoments both = a.moments;
    both += b.moments;
    return residualSumOfSquares(both) - a.residual_ss_m2 - b.residual_ss_m2 <= max_rise;
  }

  double max_gap_sq;
  double sin_max_angle;
  double max_line_distance;
  double max_rise;
  bool noise_gate;
};

}  // namespace

bool CascadeFilter::canFuse(const Segment& a, const Segment& b, const FusionParams& p,
                            const SensorNoise& noise) {
  return FusionGate(p, noise)(a, b);
}

void CascadeFilter::fuse(const SegmentLevel& in, SegmentLevel& out, const FusionParams& params,
                         bool wraps_around) const {
  out.segments.clear();
  out.parts.assign(in.parts.begin(), in.parts.end());
  if (in.segments.empty()) return;

  const FusionGate canFuseWith(params, noise_);
  // Fusing consecutive segments keeps each segment's parts contiguous in `parts`.
  Segment current = in.segments.front();
  for (std::size_t j = 1; j < in.segments.size(); ++j) {
    const Segment& next = in.segments[j];
    if (canFuseWith(current, next)) {
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
  if (!canFuseWith(out.segments.back(), out.segments.front())) return;
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
