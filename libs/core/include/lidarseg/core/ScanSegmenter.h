#pragma once
/// @file ScanSegmenter.h
/// The segmentation pipeline: Wall-Danielsson followed by the cascade filter.

#include "lidarseg/core/CascadeFilter.h"
#include "lidarseg/core/Scan.h"
#include "lidarseg/core/Segmentation.h"
#include "lidarseg/core/SensorNoise.h"
#include "lidarseg/core/WallDanielssonSegmenter.h"

namespace lidarseg {

/// Every parameter of the segmentation pipeline (paper section II).
struct SegmentationParams {
  SensorNoise noise;
  WallDanielssonParams wall_danielsson;
  CascadeParams cascade;

  /// @throws std::invalid_argument naming the first bad key.
  void validate() const;
};

/// Segments a scan at all four cascade levels (paper II.A then II.B).
class ScanSegmenter {
 public:
  /// @throws std::invalid_argument when a parameter is out of range.
  explicit ScanSegmenter(const SegmentationParams& params = {});

  /// Segments `scan` into `out`, reusing its buffers.
  /// @throws std::invalid_argument if the scan is inconsistent (see Scan::validate()).
  void process(const Scan& scan, Segmentation& out) const;

  /// The same for a moving sensor (rolling-shutter correction, see
  /// WallDanielssonSegmenter::segment()).
  void process(const Scan& scan, Segmentation& out, const Twist2D& motion) const;

  /// Convenience overload returning a new Segmentation.
  Segmentation process(const Scan& scan) const;

  const SegmentationParams& params() const { return params_; }
  const WallDanielssonSegmenter& wallDanielsson() const { return wall_danielsson_; }
  const CascadeFilter& cascade() const { return cascade_; }

 private:
  SegmentationParams params_;
  WallDanielssonSegmenter wall_danielsson_;
  CascadeFilter cascade_;
};

}  // namespace lidarseg
