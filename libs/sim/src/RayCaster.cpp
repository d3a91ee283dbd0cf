#include "lidarseg/sim/RayCaster.h"

#include <algorithm>
#include <cmath>

namespace lidarseg::sim {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Grid cells are padded so that walls touching a cell's border are listed in both cells.
constexpr double kPad = 1e-9;

// Whether segment ab crosses the axis-aligned box [lo, hi] (separating axis test).
bool segmentTouchesBox(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  if (std::max(a.x(), b.x()) < lo.x() || std::min(a.x(), b.x()) > hi.x() ||
      std::max(a.y(), b.y()) < lo.y() || std::min(a.y(), b.y()) > hi.y()) {
    return false;
  }
  // The box's corners must not all lie strictly on one side of the segment's line.
  const Eigen::Vector2d d = b - a;
  const auto side = [&](double x, double y) { return d.x() * (y - a.y()) - d.y() * (x - a.x()); };
  const double s1 = side(lo.x(), lo.y()), s2 = side(hi.x(), lo.y()), s3 = side(hi.x(), hi.y()),
               s4 = side(lo.x(), hi.y());
  const bool all_pos = s1 > 0 && s2 > 0 && s3 > 0 && s4 > 0;
  const bool all_neg = s1 < 0 && s2 < 0 && s3 < 0 && s4 < 0;
  return !(all_pos || all_neg);
}
}  // namespace

RayCaster::RayCaster(const World& world, double cell_m) : walls_(world.walls()) {
  if (walls_.empty()) return;
  Eigen::Vector2d lo = walls_[0].a, hi = walls_[0].a;
  for (const Wall& w : walls_) {
    lo = lo.cwiseMin(w.a).cwiseMin(w.b);
    hi = hi.cwiseMax(w.a).cwiseMax(w.b);
  }
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-3);
  // About two walls' worth of cells per wall, at most 1024 x 1024 cells.
  cell_ = cell_m > 0.0 ? cell_m
                       : std::max(0.25, std::sqrt(extent.x() * extent.y() /
                                                  (4.0 * static_cast<double>(walls_.size()))));
  min_ = lo - Eigen::Vector2d::Constant(cell_ * 0.5);
  // In double before the conversion: a huge extent must not overflow the int.
  nx_ = static_cast<int>(std::min(1024.0, std::ceil((extent.x() + cell_) / cell_) + 1.0));
  ny_ = static_cast<int>(std::min(1024.0, std::ceil((extent.y() + cell_) / cell_) + 1.0));
  cell_ = std::max(cell_, std::max((extent.x() + cell_) / (nx_ - 1), (extent.y() + cell_) / (ny_ - 1)));

  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(nx_) * ny_);
  for (std::uint32_t i = 0; i < walls_.size(); ++i) {
    const Wall& w = walls_[i];
    const int x0 = std::clamp(static_cast<int>((std::min(w.a.x(), w.b.x()) - min_.x()) / cell_), 0, nx_ - 1);
    const int x1 = std::clamp(static_cast<int>((std::max(w.a.x(), w.b.x()) - min_.x()) / cell_), 0, nx_ - 1);
    const int y0 = std::clamp(static_cast<int>((std::min(w.a.y(), w.b.y()) - min_.y()) / cell_), 0, ny_ - 1);
    const int y1 = std::clamp(static_cast<int>((std::max(w.a.y(), w.b.y()) - min_.y()) / cell_), 0, ny_ - 1);
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const Eigen::Vector2d clo = min_ + cell_ * Eigen::Vector2d(cx, cy) - Eigen::Vector2d::Constant(kPad);
        const Eigen::Vector2d chi = clo + Eigen::Vector2d::Constant(cell_ + 2 * kPad);
        if (segmentTouchesBox(w.a, w.b, clo, chi)) cells[static_cast<std::size_t>(cy) * nx_ + cx].push_back(i);
      }
    }
  }
  cell_start_.assign(cells.size() + 1, 0);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    cell_start_[c + 1] = cell_start_[c] + static_cast<std::uint32_t>(cells[c].size());
  }
  ids_.reserve(cell_start_.back());
  for (const auto& c : cells) ids_.insert(ids_.end(), c.begin(), c.end());
}

bool RayCaster::intersect(std::uint32_t wall, const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                          double& t) const {
  const Wall& w = walls_[wall];
  // o + t d = a + u (b - a), with 2D cross products.
  const Eigen::Vector2d e = w.b - w.a;
  const double denom = d.x() * e.y() - d.y() * e.x();
  if (std::abs(denom) < 1e-15) return false;  // parallel
  const Eigen::Vector2d ao = w.a - o;
  t = (ao.x() * e.y() - ao.y() * e.x()) / denom;
  const double u = (ao.x() * d.y() - ao.y() * d.x()) / denom;
  return t > 0.0 && u >= 0.0 && u <= 1.0;
}

RayHit RayCaster::cast(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                       double max_range_m) const {
  RayHit best;
  if (walls_.empty()) return best;
  // Enter the grid: clip the ray to the grid's box (slab method).
  const Eigen::Vector2d grid_hi = min_ + cell_ * Eigen::Vector2d(nx_, ny_);
  double t_enter = 0.0, t_leave = max_range_m;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(dir[k]) < 1e-300) {
      if (origin[k] < min_[k] || origin[k] > grid_hi[k]) return best;
      continue;
    }
    double t0 = (min_[k] - origin[k]) / dir[k], t1 = (grid_hi[k] - origin[k]) / dir[k];
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_leave = std::min(t_leave, t1);
  }
  if (t_enter > t_leave) return best;

  const Eigen::Vector2d start = origin + t_enter * dir;
  int cx = std::clamp(static_cast<int>((start.x() - min_.x()) / cell_), 0, nx_ - 1);
  int cy = std::clamp(static_cast<int>((start.y() - min_.y()) / cell_), 0, ny_ - 1);
  const int step_x = dir.x() > 0 ? 1 : -1, step_y = dir.y() > 0 ? 1 : -1;
  const double dtx = dir.x() != 0.0 ? cell_ / std::abs(dir.x()) : kInf;
  const double dty = dir.y() != 0.0 ? cell_ / std::abs(dir.y()) : kInf;
  const double next_x = min_.x() + (cx + (step_x > 0 ? 1 : 0)) * cell_;
  const double next_y = min_.y() + (cy + (step_y > 0 ? 1 : 0)) * cell_;
  double tmx = dir.x() != 0.0 ? (next_x - origin.x()) / dir.x() : kInf;
  double tmy = dir.y() != 0.0 ? (next_y - origin.y()) / dir.y() : kInf;

  while (true) {
    const std::size_t c = static_cast<std::size_t>(cy) * nx_ + cx;
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      double t;
      if (intersect(ids_[k], origin, dir, t) && t < best.range && t <= max_range_m) {
        best.range = t;
        best.wall = ids_[k];
      }
    }
    const double t_exit = std::min(tmx, tmy);
    if (best.range <= t_exit || t_exit > t_leave) break;
    if (tmx < tmy) {
      cx += step_x;
      tmx += dtx;
      if (cx < 0 || cx >= nx_) break;
    } else {
      cy += step_y;
      tmy += dty;
      if (cy < 0 || cy >= ny_) break;
    }
  }
  return best;
}

}  // namespace lidarseg::sim
