#pragma once
/// @file Segmentation.h
/// The segments of one scan at every level of the cascade filter (paper Fig. 2).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Segment.h"

namespace lidarseg {

/// Levels of the cascade filter (paper II.B, Fig. 2). Each level is computed from the
/// previous one and all stay accessible.
enum class CascadeLevel : std::size_t {
  kWallDanielsson = 0,  ///< raw Wall-Danielsson segments (the "low level")
  kFused = 1,           ///< after the first fusion
  kEroded = 2,          ///< after the erosion of short segments
  kFusedAgain = 3,      ///< after the second fusion (the "high level")
};

/// Number of cascade levels (0..3).
inline constexpr std::size_t kNumCascadeLevels = 4;

/// Human-readable name of a level ("wall-danielsson", "fused", "eroded", "fused-again").
const char* toString(CascadeLevel level);

/// The segments of one level, in scan order.
struct SegmentLevel {
  std::vector<Segment> segments;
  /// Indices of level-0 segments; Segment::parts_begin/parts_end index into this.
  std::vector<std::uint32_t> parts;

  void clear() {
    segments.clear();
    parts.clear();
  }
};

/// Result of segmenting one scan: its points and its segments at each cascade level.
///
/// Reuse one object across scans: its buffers keep their capacity, so steady-state
/// processing does not allocate.
struct Segmentation {
  /// Point of every beam in the sensor frame (m); NaN for an invalid beam.
  std::vector<Eigen::Vector2d> points;
  /// Number of valid beams.
  std::size_t num_valid_beams = 0;
  /// Whether the scan covers a full turn (segments may cross the wrap-around).
  bool wraps_around = false;
  /// Segments at each level; index with CascadeLevel.
  std::array<SegmentLevel, kNumCascadeLevels> levels;

  const SegmentLevel& level(CascadeLevel l) const { return levels[static_cast<std::size_t>(l)]; }
  SegmentLevel& level(CascadeLevel l) { return levels[static_cast<std::size_t>(l)]; }

  /// The scan points of segment `index` of level `l`, in scan order (allocates: for tools
  /// and tests, not for the per-scan hot path).
  /// @throws std::out_of_range if index is not a segment of that level.
  std::vector<Eigen::Vector2d> pointsOf(CascadeLevel l, std::size_t index) const;

  void clear();
};

}  // namespace lidarseg
