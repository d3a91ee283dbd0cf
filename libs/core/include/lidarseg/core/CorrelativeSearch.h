#pragma once
/// @file CorrelativeSearch.h
/// Recovery when the motion prior is wrong: a bounded correlative search around it
/// (Olson 2009, "Real-Time Correlative Scan Matching", the paper's reference [14]).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/core/Pose2D.h"

namespace lidarseg {

/// Parameters of the correlative search.
struct SearchParams {
  /// Half-widths of the searched window around the prior: translation (m) and rotation (rad).
  double linear_window_m = 1.2;
  double angular_window_rad = 0.6;
  /// Cell size of the keyframe's likelihood grid (m); also the translation step.
  double resolution_m = 0.05;
  /// Standard deviation of the likelihood around each keyframe point (m).
  double sigma_m = 0.08;
  /// Rotation step (rad); 0 = chosen so that the farthest used point moves by at most one
  /// cell (Olson's rule), within [0.5 deg, 2 deg]. Otherwise in [kMinAngularStepRad, 0.5].
  double angular_step_rad = 0.0;
  /// The smallest rotation step accepted (rad): with the widest window (3.15 rad) at most
  /// 12,601 rotations are tried.
  static constexpr double kMinAngularStepRad = 0.0005;
  /// Points of the current scan used at most (evenly subsampled).
  std::size_t max_points = 100;
  /// Top-level translation block of the branch and bound, in cells (>= 1); each level
  /// below halves it (rounded up) down to single cells.
  std::size_t coarse_cells = 16;
  /// Largest grid side (cells): a keyframe spanning more is clipped around the sensor.
  std::size_t max_grid_cells = 1200;

  /// @throws std::invalid_argument naming the key (as in the [search] section).
  void validate() const;
};

/// Result of a search.
struct SearchResult {
  bool found = false;
  /// Best T_key_curr found.
  Pose2D T_key_curr;
  /// Mean likelihood of the used points at the best pose (0..1) and at the prior.
  double score = 0.0;
  double prior_score = 0.0;
  /// Poses whose score was evaluated exactly, and coarse bounds evaluated.
  std::size_t evaluated = 0;
  std::size_t bounds = 0;
};

/// A keyframe rasterised for the search: its likelihood grid and, for each block size of the
/// branch and bound, the maximum of that grid over the block (keyframe sensor frame, m).
/// Depends only on the keyframe's points and the parameters, so one serves every scan matched
/// against the same keyframe.
struct SearchGrid {
  double x0 = 0.0, y0 = 0.0;  ///< corner of cell (0, 0) (m)
  double res = 0.05;          ///< cell side (m)
  int w = 0, h = 0;           ///< cells
  /// A cell's likelihood in [0, 1], quantised to 1/255 (a quarter of a float's memory: the
  /// grid is written and read once per keyframe and per search, and bandwidth is its cost).
  using Cell = std::uint8_t;
  static constexpr int kCellMax = 255;
  /// levels[l]: block side sides[l] (cells); levels.back() is the likelihood itself (side 1),
  /// levels[0] the top-level bound (side coarse_cells). Row-major, padded by `pad` cells on
  /// every side.
  std::vector<std::vector<Cell>> levels;
  std::vector<int> sides;
  /// Cells of padding on each side: the larger of sides[0] and the translation window of the
  /// parameters that prepared it, in cells.
  int pad = 0;
  /// Working buffer of prepare() (kept to reuse its allocation).
  std::vector<Cell> scratch;
  /// Whether prepare() filled it (a default grid holds no keyframe).
  bool ready = false;
};

/// Exhaustive-in-effect search of T_key_curr over a window around a prior: the keyframe's
/// points are rasterised into a likelihood grid, and every rotation step x translation cell
/// of the window is scored by the current scan's points, with a multi-level branch and bound
/// (blocks of coarse_cells, then halves, down to single cells) on sliding-maximum grids,
/// depth first, best bound first (exact: the result is the best pose of the full grid
/// search, ties going to the pose nearest the prior).
/// Points are in the sensor frames (m); invalid (non-finite) points are skipped.
/// Bounded cost: O(grid cells + rotations * (window / coarse)^2 * points + refinement).
class CorrelativeSearch {
 public:
  /// @throws std::invalid_argument for invalid parameters.
  explicit CorrelativeSearch(const SearchParams& params = {});

  SearchResult search(const std::vector<Eigen::Vector2d>& keyframe_points,
                      const std::vector<Eigen::Vector2d>& current_points, const Pose2D& prior) const;

  /// Rasterises the keyframe's points (sensor frame, m) into `grid`, reusing its buffers.
  /// Cost O(points * (sigma / resolution)^2 + cells * levels).
  void prepare(const std::vector<Eigen::Vector2d>& keyframe_points, SearchGrid& grid) const;

  /// The search against a keyframe prepared once (same result as the overload above). A
  /// non-finite prior finds nothing (`found` false).
  /// With `min_score` > 0, only poses scoring strictly above it (mean likelihood, as
  /// SearchResult::score with the same current points) are looked for: the branch and bound
  /// starts from that floor, and `found` is false when no pose beats it (a wider search after
  /// a narrower one: what the narrower one saw cannot win, and is not scored again).
  SearchResult search(const SearchGrid& grid, const std::vector<Eigen::Vector2d>& current_points,
                      const Pose2D& prior, double min_score = 0.0) const;

  const SearchParams& params() const { return params_; }

 private:
  SearchParams params_;
};

}  // namespace lidarseg
