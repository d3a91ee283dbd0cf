#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lidarseg::sim {

namespace {
// The sharpest corner a trajectory file may ask for (deg): beyond, the rounding arc has no
// room and the heading flips between two scans.
constexpr double kMaxTurnDeg = 170.0;
double wrap(double a) { return std::remainder(a, 2.0 * kPi); }
}  // namespace

Trajectory::Trajectory(std::vector<Eigen::Vector2d> wp, double speed_mps, double radius)
    : waypoints_(wp), speed_(speed_mps) {
  if (wp.size() < 2) throw std::invalid_argument("Trajectory: needs at least 2 waypoints");
  if (!(speed_mps > 0.0)) throw std::invalid_argument("Trajectory: speed must be > 0");
  if (!(radius >= 0.0)) throw std::invalid_argument("Trajectory: turn radius must be >= 0");
  for (std::size_t i = 0; i + 1 < wp.size(); ++i) {
    if ((wp[i + 1] - wp[i]).norm() < 1e-9) {
      throw std::invalid_argument("Trajectory: waypoints " + std::to_string(i) + " and " +
                                  std::to_string(i + 1) + " are equal");
    }
  }
  // Tangent length cut from each corner: d = r tan(turn / 2), at most half of either leg.
  const std::size_t n = wp.size();
  std::vector<double> cut(n, 0.0), turn(n, 0.0), r_eff(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector2d u = (wp[i] - wp[i - 1]).normalized(), v = (wp[i + 1] - wp[i]).normalized();
    turn[i] = std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
    const double half_tan = std::tan(0.5 * std::abs(turn[i]));
    if (half_tan < 1e-12 || radius == 0.0) continue;
    const double max_cut = 0.5 * std::min((wp[i] - wp[i - 1]).norm(), (wp[i + 1] - wp[i]).norm());
    cut[i] = std::min(radius * half_tan, max_cut);
    r_eff[i] = cut[i] / half_tan;
  }
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Vector2d d = (wp[i + 1] - wp[i]).normalized();
    const double heading = std::atan2(d.y(), d.x());
    Piece line{wp[i] + cut[i] * d, heading, (wp[i + 1] - wp[i]).norm() - cut[i] - cut[i + 1], 0.0, s, i};
    pieces_.push_back(line);
    s += line.length;
    if (i + 1 < n - 1 && cut[i + 1] > 0.0) {
      Piece arc{wp[i + 1] - cut[i + 1] * d, heading, r_eff[i + 1] * std::abs(turn[i + 1]),
                (turn[i + 1] > 0 ? 1.0 : -1.0) / r_eff[i + 1], s, i};
      pieces_.push_back(arc);
      s += arc.length;
    }
  }
  length_ = s;
}

Pose2D Trajectory::poseAtDistance(double s) const {
  s = std::clamp(s, 0.0, length_);
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), s,
                             [](double v, const Piece& p) { return v < p.s0; });
  const Piece& p = *(it == pieces_.begin() ? it : it - 1);
  const double ds = std::min(s - p.s0, p.length);
  if (p.curvature == 0.0) {
    return {p.start.x() + ds * std::cos(p.heading), p.start.y() + ds * std::sin(p.heading), wrap(p.heading)};
  }
  const double k = p.curvature;
  const double h = p.heading + k * ds;
  return {p.start.x() + (std::sin(h) - std::sin(p.heading)) / k,
          p.start.y() - (std::cos(h) - std::cos(p.heading)) / k, wrap(h)};
}

Pose2D Trajectory::poseAt(double t) const { return poseAtDistance(t * speed_); }

std::size_t Trajectory::legAtDistance(double s) const {
  s = std::clamp(s, 0.0, length_);
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), s, [](double v, const Piece& p) { return v < p.s0; });
  return (it == pieces_.begin() ? it : it - 1)->leg;
}

std::vector<std::pair<double, Eigen::Vector2d>> Trajectory::polyline(double tolerance_m) const {
  std::vector<std::pair<double, Eigen::Vector2d>> out;
  const auto at = [&](double s) {
    const Pose2D p = poseAtDistance(s);
    out.emplace_back(s, Eigen::Vector2d(p.x, p.y));
  };
  at(0.0);
  for (const Piece& p : pieces_) {
    std::size_t chords = 1;
    if (p.curvature != 0.0) {
      // A chord of angle a on radius r lies at most r (1 - cos(a / 2)) from its arc.
      const double r = 1.0 / std::abs(p.curvature);
      const double a_max = tolerance_m < r ? 2.0 * std::acos(1.0 - tolerance_m / r) : kPi;
      const double angle = p.length * std::abs(p.curvature);
      chords = static_cast<std::size_t>(std::clamp(std::ceil(angle / std::max(a_max, 1e-6)), 1.0, 1e5));
    }
    for (std::size_t k = 1; k <= chords; ++k) at(p.s0 + p.length * static_cast<double>(k) / static_cast<double>(chords));
  }
  return out;
}

std::optional<WallCrossing> firstWallCrossing(const World& world, const Trajectory& trajectory) {
  constexpr double kChordToleranceM = 1e-3;
  const auto points = trajectory.polyline(kChordToleranceM);
  const auto& walls = world.walls();
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const Eigen::Vector2d p = points[k].second, d = points[k + 1].second - p;
    if (!(d.squaredNorm() > 0.0)) continue;
    std::optional<WallCrossing> first;
    double first_t = 2.0;
    for (std::size_t w = 0; w < walls.size(); ++w) {
      // p + t d = a + u e, solved with 2D cross products; touching counts (t, u in [0, 1]).
      const Eigen::Vector2d e = walls[w].b - walls[w].a, ap = walls[w].a - p;
      const double denom = d.x() * e.y() - d.y() * e.x();
      if (std::abs(denom) < 1e-15) continue;  // parallel: a path along a wall's line does not cross it
      const double t = (ap.x() * e.y() - ap.y() * e.x()) / denom;
      const double u = (ap.x() * d.y() - ap.y() * d.x()) / denom;
      if (t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0 && t < first_t) {
        first_t = t;
        first = WallCrossing{points[k].first + t * (points[k + 1].first - points[k].first), p + t * d, w};
      }
    }
    if (first) return first;
  }
  return std::nullopt;
}

std::optional<std::size_t> clutterHolding(const World& world, const Eigen::Vector2d& point) {
  // Sides of clutter crossed by the ray from `point` along +x (half-open in y: a corner on
  // the ray counts once); odd: inside.
  std::size_t crossings = 0;
  std::optional<std::size_t> nearest;
  double nearest_x = 0.0;
  const auto& walls = world.walls();
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (walls[w].kind != SurfaceKind::kClutter) continue;
    const Eigen::Vector2d& a = walls[w].a;
    const Eigen::Vector2d& b = walls[w].b;
    if ((a.y() <= point.y()) == (b.y() <= point.y())) continue;
    const double x = a.x() + (point.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
    if (x <= point.x()) continue;
    ++crossings;
    if (!nearest || x < nearest_x) {
      nearest = w;
      nearest_x = x;
    }
  }
  if (crossings % 2 == 1) return nearest;
  return std::nullopt;
}

Trajectory loadTrajectoryFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open trajectory file '" + path + "'");
  double speed = 1.0, radius = 0.5;
  std::vector<Eigen::Vector2d> points;
  std::string text;
  int speed_line = 0, radius_line = 0;
  for (int line = 1; std::getline(in, text); ++line) {
    // An editor's UTF-8 byte-order mark is no part of the first line.
    if (line == 1 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
    const auto fail = [&](const std::string& m) {
      throw std::runtime_error(path + ":" + std::to_string(line) + ": " + m);
    };
    if (const auto h = text.find('#'); h != std::string::npos) text.erase(h);
    std::istringstream words(text);
    std::vector<std::string> t;
    for (std::string w; words >> w;) t.push_back(w);
    if (t.empty()) continue;
    const std::size_t want = t[0] == "waypoint" ? 3 : 2;
    if (t[0] != "waypoint" && t[0] != "speed" && t[0] != "turn_radius") {
      fail("unknown keyword '" + t[0] + "' (speed, turn_radius, waypoint)");
    }
    if (t.size() != want) fail("'" + t[0] + "' expects " + std::to_string(want - 1) + " numbers, got " + std::to_string(t.size() - 1));
    std::vector<double> v;
    for (std::size_t i = 1; i < t.size(); ++i) {
      const ParsedNumber parsed = parseNumber(t[i]);
      const double x = parsed.value;
      if (!parsed.ok() || !std::isfinite(x)) fail("'" + t[i] + "' is not a number");
      if (std::abs(x) > 1e6) fail("'" + t[i] + "' is out of range (|value| <= 1e6)");
      v.push_back(x);
    }
    // One speed and one radius for the whole path: a second value would silently replace
    // the first everywhere.
    const auto once = [&](int& first) {
      if (first != 0) fail("'" + t[0] + "' given twice (first at line " + std::to_string(first) + "): one value holds for the whole path");
      first = line;
    };
    if (t[0] == "speed") {
      once(speed_line);
      if (!(v[0] > 0.0)) fail("speed must be > 0");
      speed = v[0];
    } else if (t[0] == "turn_radius") {
      once(radius_line);
      if (!(v[0] >= 0.0)) fail("turn_radius must be >= 0");
      radius = v[0];
    } else {
      const Eigen::Vector2d next(v[0], v[1]);
      if (!points.empty() && (points.back() - next).norm() < 1e-9) fail("waypoint equal to the previous one");
      if (points.size() >= 2) {
        // A path that turns back on itself cannot be rounded into a drivable arc: the robot
        // would flip its heading between two scans.
        const Eigen::Vector2d in_dir = points.back() - points[points.size() - 2], out_dir = next - points.back();
        const double turn_deg =
            std::abs(std::atan2(in_dir.x() * out_dir.y() - in_dir.y() * out_dir.x(), in_dir.dot(out_dir))) * 180.0 / kPi;
        if (turn_deg > kMaxTurnDeg) {
          fail("the path turns back by " + numberText(turn_deg) + " deg at the waypoint before this one (at most " +
               numberText(kMaxTurnDeg) + " deg can be driven): add waypoints to turn around");
        }
      }
      points.push_back(next);
    }
  }
  if (points.size() < 2) throw std::runtime_error(path + ": needs at least 2 waypoints");
  try {
    return Trajectory(points, speed, radius);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace lidarseg::sim
