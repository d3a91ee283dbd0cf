#include "lidarseg/sim/FeatureOracle.h"
#include "lidarseg/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lidarseg/sim/OdometrySimulator.h"

namespace lidarseg::sim {

namespace {
constexpr double kSamePoint = 1e-3;        // m: endpoints this close are one corner
constexpr double kHiddenTolerance = 0.05;  // m

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Angle under which the points a and b are seen from `from` (rad, in [0, pi]).
double subtended(const Eigen::Vector2d& from, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d da = a - from, db = b - from;
  return std::abs(std::remainder(std::atan2(db.y(), db.x()) - std::atan2(da.y(), da.x()), 2 * kPi));
}
}  // namespace

FeatureOracle::FeatureOracle(const World& world, const FeatureOracleParams& params)
    : world_(&world), params_(params), caster_(world) {
  if (!(params.corner_min_angle_deg > 0 && params.corner_max_angle_deg < 180 &&
        params.corner_min_angle_deg <= params.corner_max_angle_deg)) {
    throw std::invalid_argument("FeatureOracle: corner angle range must lie in (0, 180) deg");
  }
  const auto& walls = world.walls();
  const double cos_lo = std::cos(params.corner_min_angle_deg * kPi / 180.0);
  const double cos_hi = std::cos(params.corner_max_angle_deg * kPi / 180.0);
  auto usable = [&](const Wall& w) {
    return w.kind != SurfaceKind::kDoor && (w.b - w.a).norm() >= params.min_wall_m;
  };
  auto add = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& oa, const Eigen::Vector2d& ob) {
    const double la = oa.norm(), lb = ob.norm();
    if (la < params.min_wall_m || lb < params.min_wall_m) return;
    const Eigen::Vector2d ua = oa / la, ub = ob / lb;
    const double c = ua.dot(ub);
    if (c > cos_lo || c < cos_hi) return;
    for (const Corner& k : corners_) {  // the same corner from another pair of pieces
      if ((k.point - p).norm() < kSamePoint &&
          ((k.toward_a - ua).norm() < 1e-6 || (k.toward_b - ua).norm() < 1e-6) &&
          ((k.toward_a - ub).norm() < 1e-6 || (k.toward_b - ub).norm() < 1e-6)) {
        return;
      }
    }
    for (const Door& d : world.doors()) {  // a jamb's corner belongs to its door
      const Eigen::Vector2d back = std::max(d.wall_thickness_m, d.recess_m) * d.behind();
      for (const Eigen::Vector2d& j : {d.jamb_a, d.jamb_b, Eigen::Vector2d(d.jamb_a + back),
                                       Eigen::Vector2d(d.jamb_b + back)}) {
        if ((j - p).norm() <= params.door_exclusion_m) return;
      }
    }
    corners_.push_back({p, ua, ub, la, lb});
  };
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const Wall& a = walls[i];
    if (!usable(a)) continue;
    for (std::size_t j = 0; j < walls.size(); ++j) {
      if (j == i) continue;
      const Wall& b = walls[j];
      if (!usable(b)) continue;
      const Eigen::Vector2d eb = b.b - b.a;
      const double len_b = eb.norm();
      for (const Eigen::Vector2d* pa : {&a.a, &a.b}) {
        const Eigen::Vector2d oa = (pa == &a.a ? a.b : a.a) - *pa;
        // Shared endpoint (each pair once: j > i).
        if (j > i) {
          for (const Eigen::Vector2d* pb : {&b.a, &b.b}) {
            if ((*pa - *pb).norm() > kSamePoint) continue;
            add(*pa, oa, (pb == &b.a ? b.b : b.a) - *pb);
          }
        }
        // A's endpoint on (or within touch_m of) B's interior: a T, one corner on each side
        // of A, at the foot of the endpoint on B.
        const double s = (*pa - b.a).dot(eb) / (len_b * len_b);
        const double off = std::abs(cross(eb / len_b, *pa - b.a));
        if (off > params.touch_m || s * len_b <= kSamePoint || (1 - s) * len_b <= kSamePoint) continue;
        const Eigen::Vector2d foot = b.a + s * eb;
        add(foot, oa + (*pa - foot), b.a - foot);
        add(foot, oa + (*pa - foot), b.b - foot);
      }
      // Interiors crossing (an X): four corners.
      if (j > i) {
        const Eigen::Vector2d ea = a.b - a.a;
        const double den = cross(ea, eb);
        if (std::abs(den) < 1e-12) continue;
        const double ta = cross(b.a - a.a, eb) / den;
        const double tb = cross(b.a - a.a, ea) / den;
        const double la = ea.norm();
        if (ta * la <= kSamePoint || (1 - ta) * la <= kSamePoint || tb * len_b <= kSamePoint ||
            (1 - tb) * len_b <= kSamePoint) {
          continue;
        }
        const Eigen::Vector2d x = a.a + ta * ea;
        for (const Eigen::Vector2d* pa : {&a.a, &a.b}) {
          for (const Eigen::Vector2d* pb : {&b.a, &b.b}) add(x, *pa - x, *pb - x);
        }
      }
    }
  }
}

bool FeatureOracle::inView(const Pose2D& T, const BeamLayout& layout, double max_range_m,
                           const Eigen::Vector2d& p, Eigen::Vector2d& local) const {
  const Pose2D l = relative({p.x(), p.y(), 0.0}, T);
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
  if (dist < 1e-9) return false;
  return caster_.cast(from, d / dist, dist + 1.0).range >= dist - kHiddenTolerance;
}

bool FeatureOracle::seenWithBeams(const Eigen::Vector2d& from, const Eigen::Vector2d& a,
                                  const Eigen::Vector2d& b, double step_rad, std::size_t min_beams) const {
  // Points just inside both ends and the middle are reachable.
  const Eigen::Vector2d e = b - a;
  for (double f : {0.05, 0.5, 0.95}) {
    if (!reachable(from, a + f * e)) return false;
  }
  return subtended(from, a, b) >= static_cast<double>(min_beams) * step_rad;
}

std::vector<Feature> FeatureOracle::visible(const Pose2D& T, const BeamLayout& layout,
                                            double max_range_m) const {
  std::vector<Feature> out;
  const Eigen::Vector2d origin(T.x, T.y);
  const double step = layout.size() >= 2 ? std::abs(layout.angle(1) - layout.angle(0)) : 1.0;
  const FeatureOracleParams& p = params_;
  Eigen::Vector2d local, unused;
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
    const Eigen::Vector2d u = (d.jamb_b - d.jamb_a).normalized();
    Eigen::Vector2d normal(-u.y(), u.x());
    if (normal.dot(d.centre() - origin) < 0) normal = -normal;  // away from the sensor
    Feature f;
    f.type = d.kind == DoorKind::kOpen     ? FeatureType::kDoorOpen
             : d.kind == DoorKind::kClosed ? FeatureType::kDoorClosed
                                           : FeatureType::kDoorAjar;
    f.position = local;
    f.theta_rad = std::remainder(std::atan2(normal.y(), normal.x()) - T.yaw, 2 * kPi);
    f.width_m = d.width();
    f.id = i;
    const double gap = subtended(origin, d.jamb_a, d.jamb_b);
    const Eigen::Vector2d wall_a = d.jamb_a - p.wall_check_m * u, wall_b = d.jamb_b + p.wall_check_m * u;
    f.resolvable = inView(T, layout, max_range_m, wall_a, unused) &&
                   inView(T, layout, max_range_m, wall_b, unused) && gap >= static_cast<double>(p.min_gap_beams) * step &&
                   seenWithBeams(origin, wall_a, d.jamb_a, step, p.min_wall_beams) &&
                   seenWithBeams(origin, d.jamb_b, wall_b, step, p.min_wall_beams);
    f.seen_as = f.type;
    if (d.kind == DoorKind::kAjar) {
      // Each leaf turns about its hinge towards the side behind the wall (World::addDoor).
      const Eigen::Vector2d left = d.behind();
      const Eigen::Vector2d leaf = std::cos(d.leaf_angle_rad) * u + std::sin(d.leaf_angle_rad) * left;
      const double near_hinge = std::min(p.leaf_check_m, d.double_leaf ? 0.5 * d.width() : d.width());
      bool leaf_seen = seenWithBeams(origin, d.hingeA(), d.hingeA() + near_hinge * leaf, step, p.min_gap_beams);
      if (d.double_leaf && !leaf_seen) {
        const Eigen::Vector2d leaf_b =
            -std::cos(d.second_leaf_angle_rad) * u + std::sin(d.second_leaf_angle_rad) * left;
        leaf_seen = seenWithBeams(origin, d.hingeB(), d.hingeB() + near_hinge * leaf_b, step, p.min_gap_beams);
      }
      if (!leaf_seen) f.seen_as = FeatureType::kDoorOpen;
    }
    out.push_back(f);
  }
  for (std::size_t i = 0; i < corners_.size(); ++i) {
    const Corner& c = corners_[i];
    if (!inView(T, layout, max_range_m, c.point, local)) continue;
    if (!reachable(origin, c.point)) continue;
    // Concave when the sensor stands inside the wedge of the two walls (sees its inside).
    const Eigen::Vector2d s = origin - c.point;
    const double cross_ab = cross(c.toward_a, c.toward_b);
    const bool inside = cross_ab > 0 ? (cross(c.toward_a, s) > 0 && cross(s, c.toward_b) > 0)
                                     : (cross(c.toward_a, s) < 0 && cross(s, c.toward_b) < 0);
    Eigen::Vector2d bisector = c.toward_a + c.toward_b;
    if (!inside) bisector = -bisector;
    Feature f;
    f.type = inside ? FeatureType::kCornerConcave : FeatureType::kCornerConvex;
    f.position = local;
    f.theta_rad = std::remainder(std::atan2(bisector.y(), bisector.x()) - T.yaw, 2 * kPi);
    f.id = i;
    f.seen_as = f.type;
    const Eigen::Vector2d end_a = c.point + std::min(c.length_a, p.arm_check_m) * c.toward_a;
    const Eigen::Vector2d end_b = c.point + std::min(c.length_b, p.arm_check_m) * c.toward_b;
    f.resolvable = inView(T, layout, max_range_m, end_a, unused) && inView(T, layout, max_range_m, end_b, unused) &&
                   seenWithBeams(origin, c.point, end_a, step, p.min_arm_beams) &&
                   seenWithBeams(origin, c.point, end_b, step, p.min_arm_beams);
    out.push_back(f);
  }
  return out;
}

}  // namespace lidarseg::sim
