#include "lidarseg/sim/WorldFile.h"
#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace lidarseg::sim {

namespace {

// Shorter than this is "zero length" (m).
constexpr double kMinLength = 1e-6;
// Larger magnitudes are refused (m or degrees): far beyond any building, and far from the
// precision limits of the ray caster's arithmetic.
constexpr double kMaxMagnitude = 1e6;
// A world's size: the ground truth of corners compares every wall piece with every other and
// a door cuts every wall, so time grows with the square of these counts (50 000 walls took a
// minute to load). Generous for a building (the generated ones hold about 100 pieces).
constexpr std::size_t kMaxWallPieces = 10000;
constexpr std::size_t kMaxDoors = 1000;

class LineParser {
 public:
  LineParser(const std::string& source, int line, std::vector<std::string> tokens)
      : source_(source), line_(line), tokens_(std::move(tokens)) {}
  // The same line, other tokens.
  LineParser(const LineParser& line, std::vector<std::string> tokens)
      : source_(line.source_), line_(line.line_), tokens_(std::move(tokens)) {}

  [[noreturn]] void fail(const std::string& message) const {
    throw std::runtime_error(source_ + ":" + std::to_string(line_) + ": " + message);
  }

  // The numbers after the first `skip` tokens; exactly `count`, or between `count` and
  // `max_count` when max_count > count.
  std::vector<double> numbers(std::size_t skip, std::size_t count, std::size_t max_count) const {
    const std::size_t given = tokens_.size() - skip;
    const std::string what = tokens_[0] + (skip > 1 ? " " + tokens_[1] : std::string());
    if (given < count || given > std::max(count, max_count)) {
      fail("'" + what + "' expects " + std::to_string(count) +
           (max_count > count ? " to " + std::to_string(max_count) : std::string()) +
           " numbers, got " + std::to_string(given));
    }
    std::vector<double> v;
    for (std::size_t i = skip; i < tokens_.size(); ++i) {
      const std::string& t = tokens_[i];
      const ParsedNumber parsed = parseNumber(t);
      const double x = parsed.value;
      if (!parsed.ok() || !std::isfinite(x)) {
        fail("'" + t + "' is not a number");
      }
      if (std::abs(x) > kMaxMagnitude) fail("'" + t + "' is out of range (|value| <= 1e6)");
      v.push_back(x);
    }
    return v;
  }

  const std::vector<std::string>& tokens() const { return tokens_; }

 private:
  const std::string& source_;
  int line_;
  std::vector<std::string> tokens_;
};

Eigen::Vector2d point(const std::vector<double>& v, std::size_t i) { return {v[i], v[i + 1]}; }

bool isOption(const std::string& token) { return token == "thickness" || token == "frame" || token == "double"; }

// The options after a door's numbers: `thickness T` (m, the wall's), `frame D` (m, an ajar
// door's hinges behind the wall line), `double` (two leaves; an ajar door's second leaf
// opened ANGLE deg: `double ANGLE`).
void parseDoorOptions(const LineParser& p, const std::vector<std::string>& tokens, std::size_t at, Door& door) {
  auto value = [&](std::size_t k, const std::string& name) {
    if (k >= tokens.size() || isOption(tokens[k])) p.fail("'" + name + "' needs a value");
    return LineParser(p, {name, tokens[k]}).numbers(1, 1, 1)[0];
  };
  std::vector<std::string> given;
  while (at < tokens.size()) {
    const std::string& name = tokens[at];
    // A second value would silently replace the first.
    if (isOption(name)) {
      if (std::find(given.begin(), given.end(), name) != given.end()) p.fail("door option '" + name + "' given twice");
      given.push_back(name);
    }
    if (name == "thickness") {
      door.wall_thickness_m = value(at + 1, name);
      if (!(door.wall_thickness_m >= 0.0 && door.wall_thickness_m <= 1.0)) p.fail("wall thickness must be in [0, 1] m");
      at += 2;
    } else if (name == "frame") {
      if (door.kind != DoorKind::kAjar) p.fail("'frame' is for ajar doors (a closed door's leaf is at its recess)");
      door.recess_m = value(at + 1, name);
      if (!(door.recess_m >= 0.0 && door.recess_m <= 1.0)) p.fail("frame depth must be in [0, 1] m");
      at += 2;
    } else if (name == "double") {
      door.double_leaf = true;
      ++at;
      if (door.kind == DoorKind::kAjar) {
        const double angle = value(at, name);
        if (!(angle > 0.0 && angle <= 180.0)) p.fail("ajar door angle must be in (0, 180] deg");
        door.second_leaf_angle_rad = angle * kDegToRad;
        ++at;
      }
    } else {
      p.fail("unknown door option '" + name + "' (thickness, frame, double)");
    }
  }
}

}  // namespace

namespace {

// The same opening, whichever jamb comes first, and the same kind.
bool sameDoor(const Door& a, const Door& b) {
  constexpr double kSame = 1e-3;  // m, the tolerance doors cut walls with
  const bool jambs = ((a.jamb_a - b.jamb_a).norm() < kSame && (a.jamb_b - b.jamb_b).norm() < kSame) ||
                     ((a.jamb_a - b.jamb_b).norm() < kSame && (a.jamb_b - b.jamb_a).norm() < kSame);
  return jambs && a.kind == b.kind;
}

// Doors that would be dropped or cut into one another: a door on no wall cuts nothing and
// would be counted as ground truth the scans never show; two doors on one opening give two
// ground-truth doors for one (or an open door's leaf where a closed one stands).
void checkDoors(const World& walls, const std::vector<Door>& doors, const std::vector<int>& lines,
                const std::string& source) {
  const auto at = [&](std::size_t i) { return source + ":" + std::to_string(lines[i]); };
  for (std::size_t j = 0; j < doors.size(); ++j) {
    for (std::size_t i = 0; i < j; ++i) {
      if (sameDoor(doors[i], doors[j])) throw std::runtime_error(at(j) + ": the door of " + at(i) + " given again");
      if (overlap(doors[i], doors[j])) {
        throw std::runtime_error(at(j) + ": " + toString(doors[j].kind) + " door overlaps the " +
                                 toString(doors[i].kind) + " door of " + at(i) + " (one opening, two doors)");
      }
    }
    if (!walls.holdsDoor(doors[j])) {
      throw std::runtime_error(at(j) + ": door lies on no wall (no wall runs along its jambs' line within 1 mm)");
    }
    // A door reaching past its wall's end (or wider than it) would cut the whole wall and
    // be counted as ground truth with no wall around it.
    constexpr double kCoverTolerance = 1e-3;  // m, the tolerance doors cut walls with
    const double covered = walls.wallAlongDoor(doors[j]);
    if (covered < doors[j].width() - kCoverTolerance) {
      throw std::runtime_error(at(j) + ": door extends beyond its wall (the walls along its jambs' line hold " +
                               numberText(std::round(covered * 1e3) / 1e3) + " m of its " +
                               numberText(std::round(doors[j].width() * 1e3) / 1e3) + " m)");
    }
  }
}

}  // namespace

World parseWorld(std::istream& in, const std::string& source) {
  World world;
  std::vector<Door> doors;
  std::vector<int> door_lines;
  bool has_wall = false;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    // An editor's UTF-8 byte-order mark is no part of the first line.
    if (number == 1 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.erase(hash);
    std::istringstream words(text);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    if (tokens.empty()) continue;
    const LineParser p(source, number, tokens);

    const std::string& key = tokens[0];

    if (key == "wall") {
      const auto v = p.numbers(1, 4, 4);
      if ((point(v, 2) - point(v, 0)).norm() < kMinLength) p.fail("wall of zero length");
      world.addWall(point(v, 0), point(v, 2));
      has_wall = true;
    } else if (key == "polyline") {
      if (tokens.size() < 5 || (tokens.size() - 1) % 2 != 0) {
        p.fail("'polyline' expects an even number (>= 4) of numbers, got " +
               std::to_string(tokens.size() - 1));
      }
      const auto v = p.numbers(1, tokens.size() - 1, tokens.size() - 1);
      std::vector<Eigen::Vector2d> corners;
      for (std::size_t i = 0; i < v.size(); i += 2) {
        if (!corners.empty() && (point(v, i) - corners.back()).norm() < kMinLength) {
          p.fail("polyline has a side of zero length at point " + std::to_string(i / 2 + 1));
        }
        corners.push_back(point(v, i));
      }
      world.addPolyline(corners);
      has_wall = true;
    } else if (key == "door") {
      if (tokens.size() < 2) p.fail("'door' needs a kind: open, closed or ajar");
      Door door;
      const std::string& kind = tokens[1];
      // The door's numbers, then its options (keywords, each with its value).
      std::size_t options = 2;
      while (options < tokens.size() && !isOption(tokens[options])) ++options;
      const LineParser head(source, number, {tokens.begin(), tokens.begin() + static_cast<long>(options)});
      std::vector<double> v;
      if (kind == "open") {
        door.kind = DoorKind::kOpen;
        v = head.numbers(2, 4, 4);
      } else if (kind == "closed") {
        door.kind = DoorKind::kClosed;
        v = head.numbers(2, 5, 5);
        if (!(v[4] >= 0.0 && v[4] <= 1.0)) p.fail("closed door recess must be in [0, 1] m");
        door.recess_m = v[4];
      } else if (kind == "ajar") {
        door.kind = DoorKind::kAjar;
        v = head.numbers(2, 5, 5);
        if (!(v[4] > 0.0 && v[4] <= 180.0)) p.fail("ajar door angle must be in (0, 180] deg");
        door.leaf_angle_rad = v[4] * kDegToRad;
      } else {
        p.fail("unknown door kind '" + kind + "' (open, closed or ajar)");
      }
      door.jamb_a = point(v, 0);
      door.jamb_b = point(v, 2);
      if (door.width() < kMinLength) p.fail("door of zero width");
      parseDoorOptions(p, tokens, options, door);
      doors.push_back(door);
      door_lines.push_back(number);
    } else if (key == "pillar") {
      const auto v = p.numbers(1, 3, 3);
      if (!(v[2] > 0.0)) p.fail("pillar size must be > 0");
      const double h = 0.5 * v[2];
      world.addPolygon({{v[0] - h, v[1] - h}, {v[0] + h, v[1] - h}, {v[0] + h, v[1] + h},
                        {v[0] - h, v[1] + h}},
                       SurfaceKind::kClutter);
    } else if (key == "box") {
      const auto v = p.numbers(1, 4, 5);
      if (!(v[2] > 0.0 && v[3] > 0.0)) p.fail("box width and depth must be > 0");
      const double yaw = v.size() > 4 ? v[4] * kDegToRad : 0.0;
      const Eigen::Vector2d c(v[0], v[1]);
      const Eigen::Vector2d u(std::cos(yaw), std::sin(yaw)), w(-u.y(), u.x());
      const Eigen::Vector2d hu = 0.5 * v[2] * u, hw = 0.5 * v[3] * w;
      world.addPolygon({c - hu - hw, c + hu - hw, c + hu + hw, c - hu + hw}, SurfaceKind::kClutter);
    } else {
      p.fail("unknown keyword '" + key + "' (wall, polyline, door, pillar, box)");
    }
    if (world.walls().size() > kMaxWallPieces) {
      p.fail("more than " + std::to_string(kMaxWallPieces) +
             " wall pieces (walls, polyline segments, pillar and box sides): a world is capped there");
    }
    if (doors.size() > kMaxDoors) p.fail("more than " + std::to_string(kMaxDoors) + " doors: a world is capped there");
  }
  if (!has_wall) throw std::runtime_error(source + ": no walls (a world needs at least one 'wall' or 'polyline')");

  checkDoors(world, doors, door_lines, source);
  for (const Door& d : doors) world.addDoor(d);
  return world;
}

World loadWorldFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open world file '" + path + "'");
  return parseWorld(in, path);
}

}  // namespace lidarseg::sim
