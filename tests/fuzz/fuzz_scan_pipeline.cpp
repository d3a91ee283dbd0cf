/// @file fuzz_scan_pipeline.cpp
/// libFuzzer target: the core on arbitrary ranges. The input chooses the sensor (beams,
/// field of view, per-beam times), a few parameters, the ranges of a scan (NaN, inf,
/// negative, zero and huge values included) and a second scan made of the first one
/// shifted and perturbed; both go through the segmentation (every cascade level), the
/// door and corner detector, the matcher and the odometry.

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "FuzzInput.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/SegmentOdometry.h"

using namespace lidarseg;

namespace {

double rangeOf(std::uint16_t code) {
  switch (code) {
    case 0xFFFF: return std::numeric_limits<double>::quiet_NaN();
    case 0xFFFE: return std::numeric_limits<double>::infinity();
    case 0xFFFD: return -std::numeric_limits<double>::infinity();
    case 0xFFFC: return -1.0;
    case 0xFFFB: return 1e12;
    case 0xFFFA: return std::numeric_limits<double>::denorm_min();
    default: return code / 1000.0;  // 0 .. 65.5 m in millimetres
  }
}

bool finitePose(const Pose2D& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw); }

void checkSegmentation(const Segmentation& s, std::size_t beams) {
  // A segment runs from first_beam to last_beam; across the end of a 360-degree scan only,
  // first_beam > last_beam.
  for (std::size_t l = 1; l < kNumCascadeLevels; ++l) {
    fuzz::require(s.levels[l].segments.size() <= s.levels[l - 1].segments.size(), "levels never gain segments");
  }
  for (const auto& level : s.levels) {
    for (const Segment& seg : level.segments) {
      fuzz::require(seg.first_beam < beams && seg.last_beam < beams, "segment beams inside the scan");
      fuzz::require(seg.first_beam <= seg.last_beam || s.wraps_around, "segments cross the scan's end only in a full turn");
      const bool finite = std::isfinite(seg.rho_m) && std::isfinite(seg.theta_rad) && std::isfinite(seg.length_m) &&
                          seg.cog.allFinite() && seg.covariance.allFinite();
      if (!finite) {
        std::fprintf(stderr, "level %zu segment beams %u..%u points %u: rho %g theta %g length %g cog %g %g cov %g %g %g\n",
                     static_cast<std::size_t>(&level - &s.levels[0]), seg.first_beam, seg.last_beam, seg.num_points,
                     seg.rho_m, seg.theta_rad, seg.length_m, seg.cog.x(), seg.cog.y(), seg.covariance(0, 0),
                     seg.covariance(0, 1), seg.covariance(1, 1));
      }
      fuzz::require(finite, "segment lines are finite");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const std::size_t beams = 1 + in.u16() % 3000;
  const double fov = in.in(0.05, 2.0 * M_PI);
  const std::uint8_t flags = in.u8();

  OdometryParams params;
  params.segmentation.wall_danielsson.threshold_m = in.in(0.002, 0.2);
  params.segmentation.cascade.first_fusion.max_line_distance_m = in.in(0.005, 0.3);
  params.matcher.band_half_width = in.u8() % 6;
  params.matcher.iterations = in.u8() % 4;
  params.matcher.max_segments = 2 + in.u8() % 64;
  params.level = static_cast<CascadeLevel>(in.u8() % kNumCascadeLevels);
  params.deskew = (flags & 1) != 0;
  params.scanner_rotation_hz = (flags & 2) ? in.in(1.0, 50.0) : 0.0;

  auto layout = std::make_shared<const BeamLayout>(BeamLayout::centred(beams, fov));
  Scan a;
  a.layout = layout;
  a.max_range_m = (flags & 4) ? 30.0 : std::numeric_limits<double>::infinity();
  a.ranges_m.resize(beams);
  for (double& r : a.ranges_m) r = rangeOf(in.u16());
  if (flags & 8) {
    a.time_offsets_s.resize(beams);
    for (std::size_t i = 0; i < beams; ++i) a.time_offsets_s[i] = 0.025 * static_cast<double>(i) / static_cast<double>(beams);
  }
  Scan b = a;
  b.stamp_s = (flags & 16) ? a.stamp_s : 0.1;  // a repeated stamp, or 10 Hz
  const std::size_t shift = in.u8() % 8;
  for (std::size_t i = 0; i < beams; ++i) {
    b.ranges_m[i] = a.ranges_m[(i + shift) % beams] + (static_cast<int>(in.u8()) - 128) * 1e-4;
  }
  const Pose2D prior{in.in(-1, 1), in.in(-1, 1), in.in(-0.5, 0.5)};

  try {
    const SegmentOdometry probe(params);  // validates
  } catch (const std::invalid_argument&) {
    return 0;  // a parameter set out of range is refused: the contract
  }
  const ScanSegmenter segmenter(params.segmentation);
  const FeatureDetector detector;
  Segmentation sa, sb;
  try {
    segmenter.process(a, sa);
    segmenter.process(b, sb);
  } catch (const std::invalid_argument&) {
    return 0;  // a scan the core refuses (too few beams, a bad layout): a status for the app
  }
  checkSegmentation(sa, beams);
  checkSegmentation(sb, beams);
  for (const Feature& f : detector.detect(sa)) fuzz::require(f.position.allFinite(), "features are finite");

  const SegmentMatcher matcher(params.matcher);
  const auto& pa = sa.level(params.level).segments;
  const auto& pb = sb.level(params.level).segments;
  const MatchResult m = matcher.match(pa, pb, prior);
  fuzz::require(finitePose(m.T_prev_curr) && m.covariance.allFinite(), "the match is finite");
  for (const auto& [i, j] : m.matches) {
    fuzz::require(i >= 0 && static_cast<std::size_t>(i) < pa.size() && j >= 0 &&
                      static_cast<std::size_t>(j) < pb.size(),
                  "matched indices inside the inputs");
  }

  // The odometry's prior: constant velocity, the fuzzed increment, the same scaled by up to
  // 2^1000 (a finite but absurd odometry), or a non-finite one (refused).
  const std::uint8_t prior_kind = in.u8();
  const int scale = in.u8() * 4;
  std::optional<Pose2D> increment;
  if (prior_kind % 4 == 1) increment = prior;
  if (prior_kind % 4 == 2) increment = Pose2D{std::ldexp(prior.x, scale), std::ldexp(prior.y, scale), std::ldexp(prior.yaw, scale)};
  if (prior_kind % 4 == 3) increment = Pose2D{prior.x, std::numeric_limits<double>::quiet_NaN(), prior.yaw};
  SegmentOdometry odometry(params);
  int k = 0;
  for (const Scan* s : {&a, &b, &a}) {
    const bool first = k++ == 0;  // the first scan has no prior
    try {
      const OdometryStep step = odometry.process(*s, first ? std::nullopt : increment);
      fuzz::require(finitePose(step.T_odom_sensor) && step.increment_covariance.allFinite(), "odometry is finite");
      fuzz::require(first || prior_kind % 4 != 3, "a non-finite increment is refused");
    } catch (const std::invalid_argument&) {
    }
  }
  return 0;
}
