#pragma once
/// @file WallDanielssonSegmenter.h
/// Stage 1 of the pipeline: sequential Wall-Danielsson polygonal approximation of a scan.

#include <cstddef>

#include "lidarseg/core/Pose2D.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/core/Segmentation.h"
#include "lidarseg/core/SensorNoise.h"

namespace lidarseg {

/// Parameters of the Wall-Danielsson segmentation (paper II.A, ref. [10]).
struct WallDanielssonParams {
  /// The method's single threshold: the largest allowed ratio of the area between the
  /// polyline of the points and their chord, to the chord's length (m). Roughly, a point
  /// deviating by more than twice this from the chord ends the segment.
  double threshold_m = 0.018;
  /// A range discontinuity between consecutive beams larger than
  /// max(max_range_jump_m, max_range_jump_ratio * the smaller range) breaks a segment (m).
  double max_range_jump_m = 0.3;
  /// Relative part of the range-jump test (dimensionless), so that walls seen at a grazing
  /// angle far away are not cut at every beam.
  double max_range_jump_ratio = 0.1;
  /// Fewer consecutive points than this do not make a segment (>= 2).
  std::size_t min_points = 3;

  /// @throws std::invalid_argument naming the key (e.g. "wd_threshold_m") when a value is
  /// out of range.
  void validate() const;
};

/// Splits a scan into straight segments with the sequential Wall-Danielsson method
/// (paper II.A), applied to metric points, without the back-stepping post-process.
///
/// Walking the beams in order from a segment's first point p0, it accumulates the signed
/// area between the polyline p0..pk and the chord p0-pk; the segment ends before the first
/// point pk for which |area| / |pk - p0| exceeds the threshold. Invalid beams and range
/// jumps also end a segment. Each segment is then fitted (fitSegment()). O(N) per scan,
/// no allocation once the output's buffers have grown.
class WallDanielssonSegmenter {
 public:
  /// @throws std::invalid_argument when a parameter is out of range.
  explicit WallDanielssonSegmenter(const WallDanielssonParams& params = {},
                                   const SensorNoise& noise = {});

  /// Fills out.points, out.num_valid_beams, out.wraps_around and level 0 of `out`
  /// (other levels are cleared). An empty or all-invalid scan gives no segment.
  /// @throws std::invalid_argument if the scan is inconsistent (see Scan::validate()).
  void segment(const Scan& scan, Segmentation& out) const;

  /// The same, for a sensor moving at `motion` (its own frame) during the sweep: each beam's
  /// point is first moved from the sensor frame at its own time (Scan::time_offsets_s) to
  /// the frame at the scan's time (rolling-shutter correction, paper IV.A). Without time
  /// offsets it is segment(scan, out).
  void segment(const Scan& scan, Segmentation& out, const Twist2D& motion) const;

  const WallDanielssonParams& params() const { return params_; }

 private:
  WallDanielssonParams params_;
  SensorNoise noise_;
};

}  // namespace lidarseg
