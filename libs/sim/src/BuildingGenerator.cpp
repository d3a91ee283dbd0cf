#include "lidarseg/sim/BuildingGenerator.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <ostream>
#include <random>
#include <stdexcept>
#include <string>

#include "lidarseg/core/Angles.h"

namespace lidarseg::sim {

namespace {

// Everything generated is rounded to this (m) so that a world file written with mm
// reproduces it exactly (World::addDoor finds a door's wall within 1 mm).
constexpr double kGrid = 1e-3;
// Offset of the probes on each side of a candidate wall piece (m), well under kGrid.
constexpr double kProbe = 1e-4;
// Clutter stays this far from a corridor's ends and junctions beyond the corridor's width (m).
constexpr double kJunctionMargin = 0.8;
// Gap between a clutter item and its wall: touching (within the oracle's 5 cm) (m).
constexpr double kMaxClutterGap = 0.04;
// Clutter shallower or narrower than this is not placed (m).
constexpr double kMinClutter = 0.3;
// Pillars keep this far from the lobby's walls and from the corridor (m).
constexpr double kPillarMargin = 0.5;

// Rounded to the mm as the nearest double of k / 1000, which is what reading its text back
// gives (k * 0.001 can be one ulp off).
double q(double v) { return std::round(v / kGrid) / 1000.0; }
Eigen::Vector2d q(const Eigen::Vector2d& v) { return {q(v.x()), q(v.y())}; }
// Angles rounded to 0.1 deg as a world file writes them.
double qAngle(double rad) { return std::round(rad * kRadToDeg * 10.0) / 10.0 * kDegToRad; }

// Uniform draws defined here (std::uniform_real_distribution differs between libraries).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed * 0x9E3779B97F4A7C15ull + 0x1234567ull) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  bool chance(double p) { return unit() < p; }
  std::size_t below(std::size_t n) { return std::min(n - 1, static_cast<std::size_t>(unit() * static_cast<double>(n))); }

 private:
  std::mt19937_64 engine_;
};

// An axis-aligned rectangle of free space (m).
struct Rect {
  double x0, y0, x1, y1;
};

bool insideAny(const std::vector<Rect>& rects, double x, double y) {
  for (const Rect& r : rects) {
    if (x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1) return true;
  }
  return false;
}

long long key(double v) { return std::llround(v / kGrid); }

// The boundary of the union of the rectangles, as maximal straight walls: a piece of a
// rectangle's edge is a wall when free space lies on exactly one side of it.
std::vector<Wall> boundaryOf(const std::vector<Rect>& rects) {
  std::vector<double> xs, ys;
  for (const Rect& r : rects) {
    xs.insert(xs.end(), {r.x0, r.x1});
    ys.insert(ys.end(), {r.y0, r.y1});
  }
  auto unique_sorted = [](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end(), [](double a, double b) { return std::abs(a - b) < 0.5 * kGrid; }), v.end());
  };
  unique_sorted(xs);
  unique_sorted(ys);
  // Pieces per line, keyed by the line's coordinate: (start, end) along the line.
  std::map<long long, std::map<long long, long long>> horizontal, vertical;
  for (const Rect& r : rects) {
    for (double y : {r.y0, r.y1}) {
      for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
        if (xs[k] < r.x0 - 0.5 * kGrid || xs[k + 1] > r.x1 + 0.5 * kGrid) continue;
        const double m = 0.5 * (xs[k] + xs[k + 1]);
        if (insideAny(rects, m, y + kProbe) != insideAny(rects, m, y - kProbe)) {
          horizontal[key(y)][key(xs[k])] = key(xs[k + 1]);
        }
      }
    }
    for (double x : {r.x0, r.x1}) {
      for (std::size_t k = 0; k + 1 < ys.size(); ++k) {
        if (ys[k] < r.y0 - 0.5 * kGrid || ys[k + 1] > r.y1 + 0.5 * kGrid) continue;
        const double m = 0.5 * (ys[k] + ys[k + 1]);
        if (insideAny(rects, x + kProbe, m) != insideAny(rects, x - kProbe, m)) {
          vertical[key(x)][key(ys[k])] = key(ys[k + 1]);
        }
      }
    }
  }
  std::vector<Wall> walls;
  auto merge = [&](const std::map<long long, std::map<long long, long long>>& lines, bool is_horizontal) {
    for (const auto& [line, pieces] : lines) {
      auto it = pieces.begin();
      while (it != pieces.end()) {
        const long long from = it->first;
        long long to = it->second;
        for (++it; it != pieces.end() && it->first == to; ++it) to = it->second;
        const double c = static_cast<double>(line) * kGrid, a = static_cast<double>(from) * kGrid,
                     b = static_cast<double>(to) * kGrid;
        walls.push_back(is_horizontal ? Wall{{a, c}, {b, c}, SurfaceKind::kWall}
                                      : Wall{{c, a}, {c, b}, SurfaceKind::kWall});
      }
    }
  };
  merge(horizontal, true);
  merge(vertical, false);
  return walls;
}

// Splits [x0, x1] into rooms of width in [lo, hi] separated by walls of `thickness`.
std::vector<std::pair<double, double>> partition(Rng& rng, double x0, double x1, double lo, double hi,
                                                 double thickness) {
  std::vector<std::pair<double, double>> rooms;
  double cur = x0;
  while (x1 - cur > hi) {
    double w = q(rng.uniform(lo, hi));
    if (x1 - cur - w - thickness < lo) {
      if (x1 - cur - thickness - lo >= lo) {
        w = x1 - cur - thickness - lo;
      } else {
        break;  // the rest is one room a little wider than `hi`
      }
    }
    rooms.emplace_back(cur, cur + w);
    cur = q(cur + w + thickness);
  }
  if (x1 - cur >= lo || rooms.empty()) rooms.emplace_back(cur, x1);
  return rooms;
}

// A straight stretch of wall face along which doors and clutter are placed: the points
// origin + s * along for s in [s0, s1], free space on the side `into`.
struct Face {
  Eigen::Vector2d origin;
  Eigen::Vector2d along;
  Eigen::Vector2d into;
  double s0, s1;
  // Distance from the face to the trajectory (or the corridor's middle) (m).
  double free_depth;
  // Intervals of s without wall (junctions, a lobby) or taken by a door with its margins.
  std::vector<std::pair<double, double>> blocked;
  // Intervals kept free of clutter only: near junctions, where the trajectory turns.
  std::vector<std::pair<double, double>> no_clutter;
};

bool clear(const std::vector<std::pair<double, double>>& blocked, double a, double b) {
  for (const auto& [lo, hi] : blocked) {
    if (b > lo && a < hi) return false;
  }
  return true;
}

bool clear(const Face& f, double a, double b) {
  return a >= f.s0 && b <= f.s1 && clear(f.blocked, a, b) && clear(f.no_clutter, a, b);
}

// Where an interval of `length` may start in [lo, hi - length] without meeting `blocked`
// (each blocked interval widened by `margin`).
std::vector<std::pair<double, double>> freeStarts(double lo, double hi, double length, double margin,
                                                  const std::vector<std::pair<double, double>>& blocked) {
  std::vector<std::pair<double, double>> starts{{lo, hi - length}};
  if (hi - length < lo) return {};
  for (const auto& [b0, b1] : blocked) {
    std::vector<std::pair<double, double>> next;
    const double cut0 = b0 - margin - length, cut1 = b1 + margin;
    for (const auto& [s0, s1] : starts) {
      if (cut1 <= s0 || cut0 >= s1) {
        next.emplace_back(s0, s1);
        continue;
      }
      if (cut0 > s0) next.emplace_back(s0, cut0);
      if (cut1 < s1) next.emplace_back(cut1, s1);
    }
    starts = std::move(next);
  }
  return starts;
}

class Generator {
 public:
  Generator(std::uint64_t seed, const BuildingParams& p) : p_(p), rng_(seed) { b_.seed = seed; }

  Building run() {
    drawBuilding();
    layout();
    b_.walls = boundaryOf(free_);
    placeClutterAlongCorridors();
    // Everything as its world file will read back: sums of rounded lengths are not rounded.
    for (Wall& w : b_.walls) w = {q(w.a), q(w.b), w.kind};
    for (Clutter& c : b_.clutter) {
      c.centre = q(c.centre);
      c.width_m = q(c.width_m);
      c.depth_m = q(c.depth_m);
      c.yaw_rad = qAngle(c.yaw_rad);
    }
    for (Door& d : b_.doors) {
      d.jamb_a = q(d.jamb_a);
      d.jamb_b = q(d.jamb_b);
      d.recess_m = q(d.recess_m);
      d.wall_thickness_m = q(d.wall_thickness_m);
      d.leaf_angle_rad = qAngle(d.leaf_angle_rad);
      d.second_leaf_angle_rad = qAngle(d.second_leaf_angle_rad);
    }
    for (Eigen::Vector2d& p : b_.waypoints) p = q(p);
    return std::move(b_);
  }

 private:
  void drawBuilding() {
    b_.wall_thickness_m = q(rng_.uniform(p_.wall_min_thickness_m, p_.wall_max_thickness_m));
    b_.corridor_width_m = q(rng_.uniform(p_.corridor_min_width_m, p_.corridor_max_width_m));
    b_.open_share = rng_.uniform(0.0, p_.max_open_share);
    b_.ajar_share = rng_.uniform(0.0, p_.max_ajar_share);
    b_.double_door_share = rng_.uniform(0.0, p_.max_double_door_share);
    b_.clutter_per_m = rng_.uniform(0.0, p_.max_clutter_per_m);
    b_.has_cross_corridor = rng_.chance(p_.cross_corridor_probability);
    b_.has_lobby = rng_.chance(p_.lobby_probability);
    b_.speed_mps = p_.speed_mps;
    b_.turn_radius_m = p_.turn_radius_m;
  }

  // Path offset from a corridor's middle: anywhere keeping the clearance.
  double pathOffset() {
    const double room = std::max(0.0, 0.5 * b_.corridor_width_m - p_.path_clearance_m - 0.25);
    return q(rng_.uniform(-room, room));
  }

  // A door in `face` of a room spanning s in [r0, r1] of it; returns false when none fits.
  bool addDoor(Face& face, double r0, double r1, bool exit) {
    const double T = b_.wall_thickness_m;
    Door d;
    d.double_leaf = rng_.chance(b_.double_door_share);
    double w = d.double_leaf ? rng_.uniform(p_.double_door_min_width_m, p_.double_door_max_width_m)
                             : rng_.uniform(p_.single_door_min_width_m, p_.single_door_max_width_m);
    w = q(w);
    const double room = r1 - r0 - 2.0 * p_.door_margin_m;
    if (room < w) {
      if (room < p_.single_door_min_width_m) return false;
      d.double_leaf = false;
      w = q(rng_.uniform(p_.single_door_min_width_m, std::min(room, p_.single_door_max_width_m)));
    }
    // Anywhere in the room's wall that leaves door_margin_m of wall on both sides.
    const auto starts = freeStarts(std::max(r0, face.s0) + p_.door_margin_m, std::min(r1, face.s1) - p_.door_margin_m,
                                   w, p_.door_margin_m, face.blocked);
    double total = 0.0;
    for (const auto& [a, b] : starts) total += b - a;
    if (starts.empty()) return false;
    double pick = rng_.uniform(0.0, total), s = starts.back().second;
    for (const auto& [a, b] : starts) {
      if (pick <= b - a) {
        s = a + pick;
        break;
      }
      pick -= b - a;
    }
    s = q(s);
    // The opening runs along the face with the free space (the corridor) in front of it
    // and the room behind: behind is the left of jamb_a -> jamb_b, i.e. -into.
    const Eigen::Vector2d p0 = face.origin + s * face.along, p1 = face.origin + (s + w) * face.along;
    const bool left_is_behind = (-face.into).dot(Eigen::Vector2d(-face.along.y(), face.along.x())) > 0;
    d.jamb_a = left_is_behind ? p0 : p1;
    d.jamb_b = left_is_behind ? p1 : p0;
    d.jamb_a = {q(d.jamb_a.x()), q(d.jamb_a.y())};
    d.jamb_b = {q(d.jamb_b.x()), q(d.jamb_b.y())};
    d.wall_thickness_m = T;
    const double u = rng_.unit();
    d.kind = exit ? DoorKind::kClosed
                  : u < b_.open_share ? DoorKind::kOpen
                  : u < b_.open_share + b_.ajar_share ? DoorKind::kAjar
                                                      : DoorKind::kClosed;
    const double recess = q(rng_.uniform(0.0, std::min(p_.max_recess_m, T)));
    if (d.kind != DoorKind::kOpen) d.recess_m = recess;
    if (d.kind == DoorKind::kAjar) {
      auto angle = [&] { return std::round(rng_.uniform(p_.ajar_min_angle_deg, p_.ajar_max_angle_deg) * 10.0) / 10.0 * kDegToRad; };
      d.leaf_angle_rad = angle();
      if (d.double_leaf) d.second_leaf_angle_rad = angle();
    }
    face.blocked.emplace_back(s - p_.door_margin_m, s + w + p_.door_margin_m);
    b_.doors.push_back(d);
    return true;
  }

  // A box against the back wall of a room spanning [x0, x1] x [y0, y1], the back wall at
  // y1 when `back_high`, else y0.
  void roomClutter(const Rect& r, bool back_high) {
    if (!rng_.chance(p_.room_clutter_probability)) return;
    const double w = q(rng_.uniform(0.4, 1.2)), dp = q(rng_.uniform(kMinClutter, p_.clutter_max_depth_m));
    if (r.x1 - r.x0 < w + 1.0) return;
    const double cx = q(rng_.uniform(r.x0 + 0.5 + 0.5 * w, r.x1 - 0.5 - 0.5 * w));
    const double gap = q(rng_.uniform(0.0, kMaxClutterGap));
    const double cy = back_high ? r.y1 - gap - 0.5 * dp : r.y0 + gap + 0.5 * dp;
    b_.clutter.push_back({{cx, q(cy)}, w, dp, 0.0, false});
  }

  void layout() {
    const double T = b_.wall_thickness_m, c = b_.corridor_width_m;
    const double total = q(rng_.uniform(p_.block_min_length_m, p_.block_max_length_m));
    const double d1 = q(rng_.uniform(p_.room_min_depth_m, p_.room_max_depth_m));
    const double d2 = q(rng_.uniform(p_.room_min_depth_m, p_.room_max_depth_m));
    const double Ly = d1 + T + d2;
    // Blocks of rooms along x; a cross corridor between two of them.
    std::vector<std::pair<double, double>> blocks;
    double cross_x = 0.0;  // the cross corridor's left face
    if (b_.has_cross_corridor) {
      const double l0 = q(total * rng_.uniform(0.35, 0.65));
      cross_x = l0 + T;
      blocks = {{0.0, l0}, {q(l0 + 2 * T + c), q(total + 2 * T + c)}};
    } else {
      blocks = {{0.0, total}};
    }
    const double right = blocks.back().second;  // the block's right end
    const double xl = -T - c, xr = right + T + c;
    const double yb = -T - c, yt = Ly + T + c;
    // The ring of corridors, and the cross corridor.
    free_.push_back({xl, yb, xr, -T});
    free_.push_back({xl, Ly + T, xr, yt});
    free_.push_back({xl, yb, -T, yt});
    free_.push_back({right + T, yb, xr, yt});
    if (b_.has_cross_corridor) free_.push_back({cross_x, -T, cross_x + c, Ly + T});

    // The trajectory: the ring, or the loop through the cross corridor on one side.
    const double path_b = q(-T - 0.5 * c + pathOffset()), path_t = q(Ly + T + 0.5 * c + pathOffset());
    double path_l = q(-T - 0.5 * c + pathOffset()), path_r = q(right + T + 0.5 * c + pathOffset());
    const double path_cross = q(cross_x + 0.5 * c + pathOffset());
    bool left_half = true;
    if (b_.has_cross_corridor) {
      left_half = rng_.chance(0.5);
      (left_half ? path_r : path_l) = path_cross;
    }
    const double half_c = 0.5 * c;
    // Faces of the corridors: bottom corridor (inner face y = -T, outer y = yb), top, sides.
    Face bottom_inner{{0.0, -T}, {1.0, 0.0}, {0.0, -1.0}, -T, right + T, -T - path_b, {}, {}};
    Face bottom_outer{{0.0, yb}, {1.0, 0.0}, {0.0, 1.0}, xl, xr, path_b - yb, {}, {}};
    Face top_inner{{0.0, Ly + T}, {1.0, 0.0}, {0.0, 1.0}, -T, right + T, path_t - Ly - T, {}, {}};
    Face top_outer{{0.0, yt}, {1.0, 0.0}, {0.0, -1.0}, xl, xr, yt - path_t, {}, {}};
    Face left_outer{{xl, 0.0}, {0.0, 1.0}, {1.0, 0.0}, yb, yt, path_l - xl, {}, {}};
    Face right_outer{{xr, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, yb, yt, xr - path_r, {}, {}};
    Face left_inner{{-T, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, -T, Ly + T, -T - path_l, {}, {}};
    Face right_inner{{right + T, 0.0}, {0.0, 1.0}, {1.0, 0.0}, -T, Ly + T, path_r - right - T, {}, {}};
    // Corridors not driven: the free depth is half their width.
    const bool ring_right_driven = !b_.has_cross_corridor || !left_half;
    const bool ring_left_driven = !b_.has_cross_corridor || left_half;
    if (!ring_right_driven) right_outer.free_depth = right_inner.free_depth = half_c;
    if (!ring_left_driven) left_outer.free_depth = left_inner.free_depth = half_c;
    for (Face* f : {&bottom_inner, &bottom_outer, &top_inner, &top_outer}) {
      f->no_clutter.emplace_back(-1e9, -T + kJunctionMargin);
      f->no_clutter.emplace_back(right + T - kJunctionMargin, 1e9);
      if (b_.has_cross_corridor) {
        f->no_clutter.emplace_back(cross_x - T - kJunctionMargin, cross_x + c + T + kJunctionMargin);
      }
    }
    if (b_.has_cross_corridor) {
      for (Face* f : {&bottom_inner, &top_inner}) f->blocked.emplace_back(cross_x, cross_x + c);
    }
    // The outer faces' ends are the ring's corners: doors there would face a corridor's end.
    for (Face* f : {&bottom_outer, &top_outer}) {
      f->blocked.emplace_back(-1e9, -T);
      f->blocked.emplace_back(right + T, 1e9);
    }
    for (Face* f : {&left_outer, &right_outer, &left_inner, &right_inner}) {
      f->no_clutter.emplace_back(-1e9, -T + kJunctionMargin);
      f->no_clutter.emplace_back(Ly + T - kJunctionMargin, 1e9);
    }
    Face cross_left{{cross_x, 0.0}, {0.0, 1.0}, {1.0, 0.0}, -T, Ly + T, half_c, {}, {}};
    Face cross_right{{cross_x + c, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, -T, Ly + T, half_c, {}, {}};
    if (b_.has_cross_corridor) {
      (left_half ? cross_left : cross_right).free_depth = path_cross - cross_x;
      (left_half ? cross_right : cross_left).free_depth = cross_x + c - path_cross;
      for (Face* f : {&cross_left, &cross_right}) {
        f->no_clutter.emplace_back(-1e9, -T + kJunctionMargin);
        f->no_clutter.emplace_back(Ly + T - kJunctionMargin, 1e9);
      }
    }

    // The lobby on the top's outer side.
    double lobby0 = 0.0, lobby1 = 0.0, lobby_depth = 0.0;
    if (b_.has_lobby) {
      const double w = q(rng_.uniform(p_.lobby_min_width_m, p_.lobby_max_width_m));
      lobby_depth = q(rng_.uniform(p_.lobby_min_depth_m, p_.lobby_max_depth_m));
      const double lo = left_half || !b_.has_cross_corridor ? 0.0 : blocks.back().first;
      const double hi = left_half && b_.has_cross_corridor ? blocks.front().second : right;
      if (hi - lo > w + 1.0) {
        lobby0 = q(rng_.uniform(lo, hi - w));
        lobby1 = lobby0 + w;
        free_.push_back({lobby0, yt, lobby1, yt + lobby_depth});
        top_outer.blocked.emplace_back(lobby0, lobby1);
        top_outer.no_clutter.emplace_back(lobby0 - T - kJunctionMargin, lobby1 + T + kJunctionMargin);
      } else {
        b_.has_lobby = false;
      }
    }

    // Rooms of the blocks: doors into the ring's long corridors and into the cross corridor.
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      const auto [bx0, bx1] = blocks[k];
      const auto bottom_rooms = partition(rng_, bx0, bx1, p_.room_min_width_m, p_.room_max_width_m, T);
      const auto top_rooms = partition(rng_, bx0, bx1, p_.room_min_width_m, p_.room_max_width_m, T);
      for (std::size_t i = 0; i < bottom_rooms.size(); ++i) {
        const auto [x0, x1] = bottom_rooms[i];
        const Rect r{x0, 0.0, x1, d1};
        free_.push_back(r);
        addDoor(bottom_inner, x0, x1, false);
        roomClutter(r, true);
        sideDoor(k, i, bottom_rooms.size(), blocks.size(), r, cross_left, cross_right);
      }
      for (std::size_t i = 0; i < top_rooms.size(); ++i) {
        const auto [x0, x1] = top_rooms[i];
        const Rect r{x0, d1 + T, x1, Ly};
        free_.push_back(r);
        addDoor(top_inner, x0, x1, false);
        roomClutter(r, false);
        sideDoor(k, i, top_rooms.size(), blocks.size(), r, cross_left, cross_right);
      }
    }
    // Rooms on the outer sides of the long corridors (none where the lobby is).
    const double od_b = q(rng_.uniform(p_.room_min_depth_m, p_.room_max_depth_m));
    for (const auto& [x0, x1] : partition(rng_, xl, xr, p_.room_min_width_m, p_.room_max_width_m, T)) {
      const Rect r{x0, yb - T - od_b, x1, yb - T};
      free_.push_back(r);
      addDoor(bottom_outer, std::max(x0, -T), std::min(x1, right + T), false);
      roomClutter(r, false);
    }
    const double od_t = q(rng_.uniform(p_.room_min_depth_m, p_.room_max_depth_m));
    std::vector<std::pair<double, double>> top_spans;
    if (b_.has_lobby) {
      top_spans = {{xl, lobby0 - T}, {lobby1 + T, xr}};
    } else {
      top_spans = {{xl, xr}};
    }
    for (const auto& [s0, s1] : top_spans) {
      if (s1 - s0 < p_.room_min_width_m) continue;
      for (const auto& [x0, x1] : partition(rng_, s0, s1, p_.room_min_width_m, p_.room_max_width_m, T)) {
        const Rect r{x0, yt + T, x1, yt + T + od_t};
        free_.push_back(r);
        addDoor(top_outer, std::max(x0, -T), std::min(x1, right + T), false);
        roomClutter(r, true);
      }
    }
    // Exits in the outer walls at the ring's ends (nothing behind them).
    const std::size_t exits = rng_.below(p_.max_exits + 1);
    for (std::size_t e = 0; e < exits; ++e) {
      Face& f = e == 0 ? left_outer : right_outer;
      addDoor(f, -T, Ly + T, true);
    }
    if (b_.has_lobby) placePillars(lobby0, lobby1, yt, yt + lobby_depth);

    faces_ = {bottom_inner, bottom_outer, top_inner, top_outer, left_outer, right_outer, left_inner, right_inner};
    if (b_.has_cross_corridor) {
      faces_.push_back(cross_left);
      faces_.push_back(cross_right);
    }
    // The loop, starting and ending in the middle of the bottom corridor's driven part.
    const double start_x = q(0.5 * (path_l + path_r));
    b_.waypoints = {{start_x, path_b}, {path_r, path_b}, {path_r, path_t}, {path_l, path_t}, {path_l, path_b},
                    {start_x, path_b}};
  }

  // A door from a room next to the cross corridor into it (rooms at the blocks' facing ends).
  void sideDoor(std::size_t block, std::size_t i, std::size_t count, std::size_t blocks, const Rect& r,
                Face& cross_left, Face& cross_right) {
    if (blocks < 2 || !rng_.chance(0.5)) return;
    if (block == 0 && i + 1 == count) addDoor(cross_left, r.y0, r.y1, false);
    if (block == 1 && i == 0) addDoor(cross_right, r.y0, r.y1, false);
  }

  void placePillars(double x0, double x1, double y0, double y1) {
    const std::size_t n = rng_.below(p_.max_pillars + 1);
    for (std::size_t k = 0, tries = 0; k < n && tries < 50; ++tries) {
      const double size = q(rng_.uniform(p_.pillar_min_size_m, p_.pillar_max_size_m));
      const double m = kPillarMargin + 0.5 * size;
      if (x1 - x0 < 2 * m || y1 - y0 < 2 * m) return;
      const Eigen::Vector2d c(q(rng_.uniform(x0 + m, x1 - m)), q(rng_.uniform(y0 + m, y1 - m)));
      bool apart = true;
      for (const Clutter& o : b_.clutter) {
        if (o.pillar && (o.centre - c).norm() < 1.0 + 0.5 * (o.width_m + size)) apart = false;
      }
      if (!apart) continue;
      b_.clutter.push_back({c, size, size, 0.0, true});
      ++k;
    }
  }

  // Cabinets and bins against the corridors' walls, clear of doors and junctions and of
  // the trajectory.
  void placeClutterAlongCorridors() {
    if (b_.clutter_per_m <= 0.0) return;
    const double mean_gap = 1.0 / b_.clutter_per_m;
    for (const Face& f : faces_) {
      const double max_depth = std::min(p_.clutter_max_depth_m, f.free_depth - p_.path_clearance_m);
      double s = f.s0 + rng_.uniform(0.0, mean_gap);
      while (s < f.s1) {
        const bool bin = rng_.chance(0.3);
        const double w = q(bin ? rng_.uniform(0.3, 0.45) : rng_.uniform(0.4, 1.2));
        const double dp = q(bin ? w : rng_.uniform(kMinClutter, std::max(kMinClutter, max_depth)));
        if (dp <= max_depth && clear(f, s, s + w)) {
          const double gap = q(rng_.uniform(0.0, kMaxClutterGap));
          const Eigen::Vector2d centre = f.origin + (s + 0.5 * w) * f.along + (gap + 0.5 * dp) * f.into;
          const double yaw = std::atan2(f.along.y(), f.along.x());
          b_.clutter.push_back({{q(centre.x()), q(centre.y())}, w, dp, yaw, false});
        }
        s += w + rng_.uniform(0.3, 2.0 * mean_gap);
      }
    }
  }

  const BuildingParams& p_;
  Rng rng_;
  Building b_;
  std::vector<Rect> free_;
  std::vector<Face> faces_;
};

void requireRange(const char* lo_key, double lo, const char* hi_key, double hi, double min_allowed) {
  if (!(std::isfinite(lo) && lo >= min_allowed)) {
    throw std::invalid_argument(std::string(lo_key) + " must be finite and >= " + numberText(min_allowed) +
                                " (got " + numberText(lo) + ")");
  }
  if (!(std::isfinite(hi) && hi >= lo)) {
    throw std::invalid_argument(std::string(hi_key) + " must be finite and >= " + lo_key + " (got " +
                                numberText(hi) + ")");
  }
}

void requireShare(const char* key, double v) {
  if (!(v >= 0.0 && v <= 1.0)) {
    throw std::invalid_argument(std::string(key) + " must be in [0, 1] (got " + numberText(v) + ")");
  }
}

std::vector<Eigen::Vector2d> corners(const Clutter& c) {
  const Eigen::Vector2d u(std::cos(c.yaw_rad), std::sin(c.yaw_rad)), w(-u.y(), u.x());
  const Eigen::Vector2d hu = 0.5 * c.width_m * u, hw = 0.5 * c.depth_m * w;
  return {c.centre - hu - hw, c.centre + hu - hw, c.centre + hu + hw, c.centre - hu + hw};
}

}  // namespace

void BuildingParams::validate() const {
  requireRange("corridor_min_width_m", corridor_min_width_m, "corridor_max_width_m", corridor_max_width_m, 1.0);
  requireRange("wall_min_thickness_m", wall_min_thickness_m, "wall_max_thickness_m", wall_max_thickness_m, 0.01);
  requireRange("single_door_min_width_m", single_door_min_width_m, "single_door_max_width_m",
               single_door_max_width_m, 0.3);
  requireRange("double_door_min_width_m", double_door_min_width_m, "double_door_max_width_m",
               double_door_max_width_m, 0.3);
  requireRange("ajar_min_angle_deg", ajar_min_angle_deg, "ajar_max_angle_deg", ajar_max_angle_deg, 1.0);
  if (ajar_max_angle_deg > 90.0) {
    throw std::invalid_argument("ajar_max_angle_deg must be <= 90 (got " + numberText(ajar_max_angle_deg) + ")");
  }
  requireRange("room_min_width_m", room_min_width_m, "room_max_width_m", room_max_width_m,
               single_door_min_width_m + 2.0 * door_margin_m);
  requireRange("room_min_depth_m", room_min_depth_m, "room_max_depth_m", room_max_depth_m, 1.0);
  requireRange("block_min_length_m", block_min_length_m, "block_max_length_m", block_max_length_m,
               2.0 * room_max_width_m);
  requireRange("lobby_min_width_m", lobby_min_width_m, "lobby_max_width_m", lobby_max_width_m, 1.0);
  requireRange("lobby_min_depth_m", lobby_min_depth_m, "lobby_max_depth_m", lobby_max_depth_m, 1.0);
  requireRange("pillar_min_size_m", pillar_min_size_m, "pillar_max_size_m", pillar_max_size_m, 0.05);
  requireRange("max_recess_m", max_recess_m, "max_recess_m", max_recess_m, 0.0);
  requireRange("max_clutter_per_m", max_clutter_per_m, "max_clutter_per_m", max_clutter_per_m, 0.0);
  requireRange("clutter_max_depth_m", clutter_max_depth_m, "clutter_max_depth_m", clutter_max_depth_m, 0.3);
  requireRange("door_margin_m", door_margin_m, "door_margin_m", door_margin_m, 0.0);
  requireRange("path_clearance_m", path_clearance_m, "path_clearance_m", path_clearance_m, 0.1);
  if (2.0 * path_clearance_m + 0.2 > corridor_min_width_m) {
    throw std::invalid_argument("path_clearance_m must leave the narrowest corridor passable (got " +
                                numberText(path_clearance_m) + ")");
  }
  requireShare("max_double_door_share", max_double_door_share);
  requireShare("max_open_share", max_open_share);
  requireShare("max_ajar_share", max_ajar_share);
  if (max_open_share + max_ajar_share > 1.0) throw std::invalid_argument("max_open_share + max_ajar_share must be <= 1");
  requireShare("cross_corridor_probability", cross_corridor_probability);
  requireShare("lobby_probability", lobby_probability);
  requireShare("room_clutter_probability", room_clutter_probability);
  if (max_pillars > 100) throw std::invalid_argument("max_pillars must be <= 100 (got " + std::to_string(max_pillars) + ")");
  if (max_exits > 2) throw std::invalid_argument("max_exits must be <= 2 (got " + std::to_string(max_exits) + ")");
  if (!(speed_mps > 0.0 && std::isfinite(speed_mps))) {
    throw std::invalid_argument("speed_mps must be finite and > 0 (got " + numberText(speed_mps) + ")");
  }
  if (!(turn_radius_m >= 0.0 && turn_radius_m <= path_clearance_m + 0.5)) {
    throw std::invalid_argument("turn_radius_m must be in [0, path_clearance_m + 0.5] (got " +
                                numberText(turn_radius_m) + ")");
  }
}

World Building::world() const {
  World w(walls);
  for (const Clutter& c : clutter) w.addPolygon(corners(c), SurfaceKind::kClutter);
  for (const Door& d : doors) w.addDoor(d);
  return w;
}

Trajectory Building::trajectory() const { return Trajectory(waypoints, speed_mps, turn_radius_m); }

Building generateBuilding(std::uint64_t seed, const BuildingParams& params) {
  params.validate();
  return Generator(seed, params).run();
}

void writeWorldFile(std::ostream& os, const Building& b) {
  os << std::fixed << std::setprecision(3);
  os << "# lidarseg building " << b.seed << " (lidarseg::sim::generateBuilding): walls " << b.wall_thickness_m
     << " m thick, corridors " << b.corridor_width_m << " m wide; " << b.doors.size() << " doors\n";
  for (const Wall& w : b.walls) os << "wall " << w.a.x() << ' ' << w.a.y() << ' ' << w.b.x() << ' ' << w.b.y() << '\n';
  for (const Clutter& c : b.clutter) {
    if (c.pillar) {
      os << "pillar " << c.centre.x() << ' ' << c.centre.y() << ' ' << c.width_m << '\n';
    } else {
      os << "box " << c.centre.x() << ' ' << c.centre.y() << ' ' << c.width_m << ' ' << c.depth_m << ' '
         << std::setprecision(1) << c.yaw_rad * kRadToDeg << std::setprecision(3) << '\n';
    }
  }
  for (const Door& d : b.doors) {
    os << "door " << toString(d.kind) << ' ' << d.jamb_a.x() << ' ' << d.jamb_a.y() << ' ' << d.jamb_b.x() << ' '
       << d.jamb_b.y();
    if (d.kind == DoorKind::kClosed) os << ' ' << d.recess_m;
    if (d.kind == DoorKind::kAjar) os << ' ' << std::setprecision(1) << d.leaf_angle_rad * kRadToDeg << std::setprecision(3);
    os << " thickness " << d.wall_thickness_m;
    if (d.kind == DoorKind::kAjar) os << " frame " << d.recess_m;
    if (d.double_leaf) {
      os << " double";
      if (d.kind == DoorKind::kAjar) os << ' ' << std::setprecision(1) << d.second_leaf_angle_rad * kRadToDeg << std::setprecision(3);
    }
    os << '\n';
  }
}

void writeTrajectoryFile(std::ostream& os, const Building& b) {
  os << std::fixed << std::setprecision(3);
  os << "# lidarseg building " << b.seed << ": a loop through its corridors\n";
  os << "speed " << b.speed_mps << "\nturn_radius " << b.turn_radius_m << '\n';
  for (const Eigen::Vector2d& p : b.waypoints) os << "waypoint " << p.x() << ' ' << p.y() << '\n';
}

void writeDoorTable(std::ostream& os, const Building& b) {
  os << std::fixed << std::setprecision(3);
  os << "id,kind,width,double,recess,thickness,leaf_deg,second_leaf_deg,x,y\n";
  for (std::size_t i = 0; i < b.doors.size(); ++i) {
    const Door& d = b.doors[i];
    os << i << ',' << toString(d.kind) << ',' << d.width() << ',' << (d.double_leaf ? 1 : 0) << ',' << d.recess_m
       << ',' << d.wall_thickness_m << ',' << std::setprecision(1) << d.leaf_angle_rad * kRadToDeg << ','
       << d.second_leaf_angle_rad * kRadToDeg << std::setprecision(3) << ',' << d.centre().x() << ','
       << d.centre().y() << '\n';
  }
}

}  // namespace lidarseg::sim
