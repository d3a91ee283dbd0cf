#include "lidarseg/sim/World.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lidarseg::sim {

const char* toString(DoorKind kind) {
  switch (kind) {
    case DoorKind::kOpen:
      return "open";
    case DoorKind::kClosed:
      return "closed";
    case DoorKind::kAjar:
      return "ajar";
  }
  return "unknown";
}

Eigen::Vector2d Door::behind() const {
  const Eigen::Vector2d d = (jamb_b - jamb_a).normalized();
  return {-d.y(), d.x()};
}

Eigen::Vector2d Door::hingeA() const { return jamb_a + recess_m * behind(); }

Eigen::Vector2d Door::hingeB() const { return jamb_b + recess_m * behind(); }

namespace {
constexpr double kOnLine = 1e-3;  // m: a wall this close to the door's line holds it

// True when p lies on the line through a with unit normal `left`.
bool onLine(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& left) {
  return std::abs(left.dot(p - a)) < kOnLine;
}

// Length shared by the opening [0, width] along d from a and the segment p-q on its line.
double sharedLength(const Eigen::Vector2d& a, const Eigen::Vector2d& d, double width, const Eigen::Vector2d& p,
                    const Eigen::Vector2d& q) {
  const double tp = d.dot(p - a), tq = d.dot(q - a);
  return std::min(width, std::max(tp, tq)) - std::max(0.0, std::min(tp, tq));
}

// Walls with the part between a and b cut out, for the walls lying on the line a-b.
std::vector<Wall> cutOpening(const std::vector<Wall>& walls, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double width = (b - a).norm();
  const Eigen::Vector2d d = (b - a) / width;
  const Eigen::Vector2d left(-d.y(), d.x());
  std::vector<Wall> kept;
  kept.reserve(walls.size() + 2);
  for (const Wall& w : walls) {
    const bool on_line = onLine(w.a, a, left) && onLine(w.b, a, left);
    if (!on_line) {
      kept.push_back(w);
      continue;
    }
    // Parameters of the wall's ends along the door's direction; the door spans [0, width].
    double ta = d.dot(w.a - a), tb = d.dot(w.b - a);
    const Eigen::Vector2d pa = w.a, pb = w.b;
    const bool flipped = ta > tb;
    const Eigen::Vector2d lo = flipped ? pb : pa, hi = flipped ? pa : pb;
    if (flipped) std::swap(ta, tb);
    if (tb <= 0.0 || ta >= width) {
      kept.push_back(w);
      continue;
    }
    if (ta < 0.0) kept.push_back({lo, a, w.kind});
    if (tb > width) kept.push_back({b, hi, w.kind});
  }
  return kept;
}
}  // namespace

bool overlap(const Door& a, const Door& b) {
  const Eigen::Vector2d d = (a.jamb_b - a.jamb_a) / a.width();
  const Eigen::Vector2d left(-d.y(), d.x());
  return onLine(b.jamb_a, a.jamb_a, left) && onLine(b.jamb_b, a.jamb_a, left) &&
         sharedLength(a.jamb_a, d, a.width(), b.jamb_a, b.jamb_b) > kOnLine;
}

bool World::holdsDoor(const Door& door) const {
  const Eigen::Vector2d d = (door.jamb_b - door.jamb_a) / door.width();
  const Eigen::Vector2d left(-d.y(), d.x());
  for (const Wall& w : walls_) {
    if (onLine(w.a, door.jamb_a, left) && onLine(w.b, door.jamb_a, left) &&
        sharedLength(door.jamb_a, d, door.width(), w.a, w.b) > kOnLine) {
      return true;
    }
  }
  return false;
}

double World::wallAlongDoor(const Door& door) const {
  const Eigen::Vector2d d = (door.jamb_b - door.jamb_a) / door.width();
  const Eigen::Vector2d left(-d.y(), d.x());
  double covered = 0.0;
  for (const Wall& w : walls_) {
    if (onLine(w.a, door.jamb_a, left) && onLine(w.b, door.jamb_a, left)) {
      covered += std::max(0.0, sharedLength(door.jamb_a, d, door.width(), w.a, w.b));
    }
  }
  return covered;
}

void World::addDoor(const Door& door) {
  const Eigen::Vector2d a = door.jamb_a, b = door.jamb_b;
  const double width = (b - a).norm();
  const Eigen::Vector2d d = (b - a) / width;
  const Eigen::Vector2d left = door.behind();
  const double thickness = std::max(0.0, door.wall_thickness_m);

  walls_ = cutOpening(walls_, a, b);
  if (thickness > 0.0) walls_ = cutOpening(walls_, a + thickness * left, b + thickness * left);

  // The reveals: the opening's sides, through the wall and as deep as a recessed leaf.
  const double reveal = std::max(thickness, door.kind == DoorKind::kClosed ? door.recess_m : 0.0);
  if (reveal > 0.0) addWall(a, a + reveal * left);
  switch (door.kind) {
    case DoorKind::kOpen:
      break;
    case DoorKind::kClosed: {
      const Eigen::Vector2d back = door.recess_m * left;
      addWall(a + back, b + back, SurfaceKind::kDoor);
      break;
    }
    case DoorKind::kAjar: {
      // Each leaf turns about its hinge towards the "behind" side.
      const double leaf_len = door.double_leaf ? 0.5 * width : width;
      const double c = std::cos(door.leaf_angle_rad), s = std::sin(door.leaf_angle_rad);
      addWall(door.hingeA(), door.hingeA() + leaf_len * (c * d + s * left), SurfaceKind::kDoor);
      if (door.double_leaf) {
        const double c2 = std::cos(door.second_leaf_angle_rad), s2 = std::sin(door.second_leaf_angle_rad);
        addWall(door.hingeB(), door.hingeB() + leaf_len * (-c2 * d + s2 * left), SurfaceKind::kDoor);
      }
      break;
    }
  }
  if (reveal > 0.0) addWall(b + reveal * left, b);
  doors_.push_back(door);
}

void World::addPolygon(const std::vector<Eigen::Vector2d>& corners, SurfaceKind kind) {
  if (corners.size() < 2) return;
  addPolyline(corners, kind);
  addWall(corners.back(), corners.front(), kind);
}

void World::addPolyline(const std::vector<Eigen::Vector2d>& corners, SurfaceKind kind) {
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) addWall(corners[i], corners[i + 1], kind);
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
