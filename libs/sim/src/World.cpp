#include "lidarseg/sim/World.h"

#include <cmath>
#include <limits>

namespace lidarseg::sim {

void World::addPolygon(const std::vector<Eigen::Vector2d>& corners) {
  if (corners.size() < 2) return;
  addPolyline(corners);
  addWall(corners.back(), corners.front());
}

void World::addPolyline(const std::vector<Eigen::Vector2d>& corners) {
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) addWall(corners[i], corners[i + 1]);
}

double World::castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& unit_dir) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : walls_) {
    // origin + t * dir = a + u * (b - a), solved with 2D cross products.
    const Eigen::Vector2d e = w.b - w.a;
    const double denom = unit_dir.x() * e.y() - unit_dir.y() * e.x();
    if (std::abs(denom) < 1e-15) continue;  // parallel
    const Eigen::Vector2d ao = w.a - origin;
    const double t = (ao.x() * e.y() - ao.y() * e.x()) / denom;
    const double u = (ao.x() * unit_dir.y() - ao.y() * unit_dir.x()) / denom;
    if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < best) best = t;
  }
  return best;
}

}  // namespace lidarseg::sim
