#pragma once
/// @file CascadeFilter.h
/// Stage 2 of the pipeline: the cascade filter fusion -> erosion -> fusion (paper II.B).

#include <cstddef>
#include <string>

#include "lidarseg/core/Segmentation.h"
#include "lidarseg/core/Angles.h"
#include "lidarseg/core/SensorNoise.h"

namespace lidarseg {

/// When two consecutive segments are fused (paper Fig. 1): they must be parallel,
/// aligned (distance d between their lines) and close (gap D between facing endpoints).
struct FusionParams {
  /// Largest angle between the two lines (rad).
  double max_angle_rad = 5.0 * kDegToRad;
  /// "d": largest distance of the shorter segment's endpoints from the longer one's line (m).
  double max_line_distance_m = 0.04;
  /// "D": largest distance between the end of one segment and the start of the next (m).
  double max_gap_m = 0.5;
  /// Noise gate k (>= 0), an alternative to the angle and d tests for segments that are
  /// close: they also fuse when one line explains both within the sensor's noise, i.e. when
  /// fusing raises the residual sum of squares by at most (k * range_sigma_m)^2 (that rise
  /// follows sigma^2 * chi-square(2) for two pieces of one wall, so k = 3 keeps 99% of
  /// them). This repairs the short, badly oriented pieces that Wall-Danielsson cuts noisy
  /// walls into. 0 disables it (the paper's fixed tolerances only).
  double noise_gate_sigmas = 3.0;

  /// @throws std::invalid_argument naming the key, prefixed by `key_prefix`
  /// (e.g. "fusion1_max_gap_m").
  void validate(const std::string& key_prefix) const;
};

/// Which segments the erosion removes: those shorter than min_length_m or with fewer
/// than min_points points.
struct ErosionParams {
  double min_length_m = 0.3;
  std::size_t min_points = 5;

  /// @throws std::invalid_argument naming the key ("erosion_min_length_m", ...).
  void validate() const;
};

/// Parameters of the whole cascade.
struct CascadeParams {
  FusionParams first_fusion;
  ErosionParams erosion;
  /// The second fusion bridges the holes left by eroded segments (a bin or a table foot
  /// against a wall), so it accepts a larger gap by default.
  FusionParams second_fusion{5.0 * kDegToRad, 0.05, 0.8, 3.0};

  void validate() const;
};

/// The cascade filter of paper II.B: level 1 = fusion of level 0, level 2 = erosion of
/// level 1, level 3 = fusion of level 2. A fused segment is re-fitted from the union of
/// its points (via its moments, O(1)). Levels never gain segments.
/// O(number of segments), no allocation once the output's buffers have grown.
class CascadeFilter {
 public:
  /// @throws std::invalid_argument when a parameter is out of range.
  explicit CascadeFilter(const CascadeParams& params = {}, const SensorNoise& noise = {});

  /// Computes levels 1, 2 and 3 of `seg` from its level 0.
  void apply(Segmentation& seg) const;

  /// One fusion pass: merges runs of consecutive segments of `in` that satisfy `params`;
  /// with `wraps_around`, the last and first segments may merge too.
  void fuse(const SegmentLevel& in, SegmentLevel& out, const FusionParams& params,
            bool wraps_around) const;

  /// Erosion: copies the segments of `in` that are long enough into `out`.
  void erode(const SegmentLevel& in, SegmentLevel& out) const;

  /// Whether `b`, the segment following `a` in scan order, should be fused with it:
  /// close (D) and either parallel and aligned (d), or within the noise gate.
  static bool canFuse(const Segment& a, const Segment& b, const FusionParams& params,
                      const SensorNoise& noise);

  const CascadeParams& params() const { return params_; }

 private:
  CascadeParams params_;
  SensorNoise noise_;
};

}  // namespace lidarseg
