#include "lidarseg/sim/FeatureOracle.h"

#include <cmath>

#include "lidarseg/sim/OdometrySimulator.h"

namespace lidarseg::sim {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kSamePoint = 1e-3;     // m: endpoints this close are one corner
constexpr double kMinCornerDeg = 30.0;  // walls deviating less than this make no corner
constexpr double kHiddenTolerance = 0.05;  // m
}  // namespace

const char* toString(FeatureType type) {
  switch (type) {
    case FeatureType::kDoorOpen:
      return "door_open";
    case FeatureType::kDoorClosed:
      return "door_closed";
    case FeatureType::kDoorAjar:
      return "door_ajar";
    case FeatureType::kCornerConvex:
      return "corner_convex";
    case FeatureType::kCornerConcave:
      return "corner_concave";
  }
  return "unknown";
}

FeatureOracle::FeatureOracle(const World& world, double min_wall_m)
    : world_(&world), caster_(world) {
  const auto& walls = world.walls();
  const double cos_max = std::cos(kMinCornerDeg * kPi / 180.0);  // |cos| above: nearly straight
  for (std::size_t i = 0; i < walls.size(); ++i) {
    for (std::size_t j = i + 1; j < walls.size(); ++j) {
      const Wall& a = walls[i];
      const Wall& b = walls[j];
      if (a.kind == SurfaceKind::kClutter || b.kind == SurfaceKind::kClutter) continue;
      if ((a.b - a.a).norm() < min_wall_m || (b.b - b.a).norm() < min_wall_m) continue;
      for (const Eigen::Vector2d* pa : {&a.a, &a.b}) {
        for (const Eigen::Vector2d* pb : {&b.a, &b.b}) {
          if ((*pa - *pb).norm() > kSamePoint) continue;
          const Eigen::Vector2d oa = (pa == &a.a ? a.b : a.a) - *pa;
          const Eigen::Vector2d ob = (pb == &b.a ? b.b : b.a) - *pb;
          const Eigen::Vector2d ua = oa.normalized(), ub = ob.normalized();
          if (std::abs(ua.dot(ub)) > cos_max) continue;
          corners_.push_back({*pa, ua, ub});
        }
      }
    }
  }
}

bool FeatureOracle::inView(const Pose2& T, const BeamLayout& layout, double max_range_m,
                           const Eigen::Vector2d& p, Eigen::Vector2d& local) const {
  const Pose2 l = relative({p.x(), p.y(), 0.0}, T);
  local = {l.x, l.y};
  const double r = local.norm();
  if (r < 1e-6 || r >= max_range_m || layout.size() < 2) return false;
  const double a = std::atan2(local.y(), local.x());
  const double lo = std::min(layout.angles().front(), layout.angles().back());
  const double hi = std::max(layout.angles().front(), layout.angles().back());
  return layout.wrapsAround() || (a >= lo && a <= hi);
}

bool FeatureOracle::reachable(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
  const Eigen::Vector2d d = to - from;
  const double dist = d.norm();
  return caster_.cast(from, d / dist, dist + 1.0).range >= dist - kHiddenTolerance;
}

std::vector<Feature> FeatureOracle::visible(const Pose2& T, const BeamLayout& layout,
                                            double max_range_m) const {
  std::vector<Feature> out;
  const Eigen::Vector2d origin(T.x, T.y);
  Eigen::Vector2d local;
  for (std::size_t i = 0; i < world_->doors().size(); ++i) {
    const Door& d = world_->doors()[i];
    if (!inView(T, layout, max_range_m, d.centre(), local)) continue;
    bool seen = false;
    for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      if (reachable(origin, d.jamb_a + f * (d.jamb_b - d.jamb_a))) {
        seen = true;
        break;
      }
    }
    if (!seen) continue;
    const Eigen::Vector2d dir = d.jamb_b - d.jamb_a;
    Feature f;
    f.type = d.kind == DoorKind::kOpen     ? FeatureType::kDoorOpen
             : d.kind == DoorKind::kClosed ? FeatureType::kDoorClosed
                                           : FeatureType::kDoorAjar;
    f.position = local;
    f.theta_rad = std::remainder(std::atan2(dir.y(), dir.x()) - T.yaw, 2 * kPi);
    f.width_m = d.width();
    f.id = i;
    out.push_back(f);
  }
  for (std::size_t i = 0; i < corners_.size(); ++i) {
    const Corner& c = corners_[i];
    if (!inView(T, layout, max_range_m, c.point, local)) continue;
    if (!reachable(origin, c.point)) continue;
    // Concave when the sensor stands inside the wedge of the two walls (sees its inside).
    const Eigen::Vector2d s = origin - c.point;
    const double cross_ab = c.toward_a.x() * c.toward_b.y() - c.toward_a.y() * c.toward_b.x();
    const double cross_as = c.toward_a.x() * s.y() - c.toward_a.y() * s.x();
    const double cross_sb = s.x() * c.toward_b.y() - s.y() * c.toward_b.x();
    const bool inside = cross_ab > 0 ? (cross_as > 0 && cross_sb > 0) : (cross_as < 0 && cross_sb < 0);
    Eigen::Vector2d bisector = c.toward_a + c.toward_b;
    if (!inside) bisector = -bisector;
    Feature f;
    f.type = inside ? FeatureType::kCornerConcave : FeatureType::kCornerConvex;
    f.position = local;
    f.theta_rad = std::remainder(std::atan2(bisector.y(), bisector.x()) - T.yaw, 2 * kPi);
    f.id = i;
    out.push_back(f);
  }
  return out;
}

}  // namespace lidarseg::sim
