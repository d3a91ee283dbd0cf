#pragma once
/// @file RayCaster.h
/// Exact ray casting against a World's walls through a uniform grid.

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Where a ray stops.
struct RayHit {
  /// Distance from the origin (m); +infinity when nothing is hit within the range.
  double range = std::numeric_limits<double>::infinity();
  /// Index of the wall hit in World::walls(); meaningless when nothing is hit.
  std::uint32_t wall = 0;

  bool hit() const { return range < std::numeric_limits<double>::infinity(); }
};

/// Casts rays against a snapshot of a World's walls. Each wall is listed in the cells of
/// a uniform grid it crosses; a ray walks the cells it crosses in order (Amanatides-Woo)
/// and stops at the first cell that holds a hit closer than the cell's exit, so a cast
/// costs O(cells crossed) instead of O(walls). Results are exact (ray-segment
/// intersection). Immutable after construction: safe to share between threads.
class RayCaster {
 public:
  /// @param cell_m grid cell size (m); 0 picks one from the world's extent and wall count.
  explicit RayCaster(const World& world, double cell_m = 0.0);

  /// First wall along origin + t * unit_dir, 0 < t <= max_range_m (world frame, m).
  RayHit cast(const Eigen::Vector2d& origin, const Eigen::Vector2d& unit_dir,
              double max_range_m = std::numeric_limits<double>::infinity()) const;

  const std::vector<Wall>& walls() const { return walls_; }

 private:
  bool intersect(std::uint32_t wall, const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                 double& t) const;

  std::vector<Wall> walls_;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero();
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_start_;  // CSR: walls of cell c are ids_[start[c]..start[c+1])
  std::vector<std::uint32_t> ids_;
};

}  // namespace lidarseg::sim
