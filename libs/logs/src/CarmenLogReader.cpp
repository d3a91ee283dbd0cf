#include "lidarseg/logs/CarmenLogReader.h"
#include "lidarseg/core/Angles.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/core/ScanRecord.h"
#include "lidarseg/core/StampPolicy.h"

#include <cerrno>
#include <cmath>
#include <optional>
#include <cstdlib>
#include <set>
#include <stdexcept>

namespace lidarseg::logs {

namespace {

constexpr std::size_t kMaxBeams = 100000;
constexpr std::size_t kMaxIssuesKept = 100;
constexpr std::size_t kMaxUnknownTypes = 100;  // distinct unknown line types counted by name

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.emplace_back(line, start, i - start);
  }
  return out;
}

// A number field; throws a message naming the field.
double number(const std::vector<std::string>& f, std::size_t i, const char* name) {
  if (i >= f.size()) throw std::invalid_argument(std::string("missing field '") + name + "'");
  const ParsedNumber v = parseNumber(f[i]);
  if (v.status == ParsedNumber::Status::not_a_number) {
    throw std::invalid_argument(std::string("field '") + name + "' = '" + f[i] + "' is not a number");
  }
  return v.value;
}

double finiteNumber(const std::vector<std::string>& f, std::size_t i, const char* name) {
  const double v = number(f, i, name);
  if (!std::isfinite(v)) {
    throw std::invalid_argument(std::string("field '") + name + "' = '" + f[i] + "' is not finite");
  }
  return v;
}

// A time stamp: finite and within kMaxLogStampS.
double stampNumber(const std::vector<std::string>& f, std::size_t i, const char* name) {
  const double v = finiteNumber(f, i, name);
  if (std::abs(v) > kMaxLogStampS) {
    throw std::invalid_argument(std::string("field '") + name + "' = '" + f[i] +
                                "' is beyond +-1e10 s (the year 2286): not a time stamp");
  }
  return v;
}

// A pose field (m or rad): finite and within kMaxLogCoordinate (1e6: 1000 km, or a heading
// of 1e6 rad, is no robot's pose; 1e308 would overflow every later difference).
double poseNumber(const std::vector<std::string>& f, std::size_t i, const char* name) {
  const double v = finiteNumber(f, i, name);
  if (std::abs(v) > kMaxLogCoordinate) {
    throw std::invalid_argument(std::string("field '") + name + "' = '" + f[i] +
                                "' is beyond +-1e6 (m or rad): not a pose");
  }
  return v;
}

std::size_t count(const std::vector<std::string>& f, std::size_t i, const char* name) {
  const double v = finiteNumber(f, i, name);
  if (v < 0.0 || v != std::floor(v) || v > static_cast<double>(kMaxBeams)) {
    throw std::invalid_argument(std::string("field '") + name + "' = '" + f[i] +
                                "' is not a count in [0, " + std::to_string(kMaxBeams) + "]");
  }
  return static_cast<std::size_t>(v);
}

bool isSickErrorCode(double r) { return r >= 81.83 || (r >= 32.763 && r <= 32.767); }

const std::set<std::string>& ignoredTypes() {
  static const std::set<std::string> types = {
      "NEFF", "SYNC", "TRUEPOS", "RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4",
      "ROBOTLASER2", "GPSNMEA", "GPSGGA", "GPSRMC", "SONAR", "BUMPER", "SCANMARK",
      "POSITIONLASER", "IMU", "VECTORMOVE", "ROBOTVELOCITY", "FOLLOWTRAJECTORY",
      "BASEVELOCITY", "ARMSTATE", "LASER1", "LASER2", "LASER3", "LASER4", "LASER5"};
  return types;
}

// Ignored line types that hold laser scans in another form (no pose, another layout): a
// log of only these has no scan this reader reads, and the error says why.
const std::set<std::string>& unreadLaserTypes() {
  static const std::set<std::string> types = {"RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4", "ROBOTLASER2",
                                              "POSITIONLASER", "LASER1", "LASER2", "LASER3", "LASER4", "LASER5"};
  return types;
}

}  // namespace

bool isLaserType(const std::string& type) {
  return type == "FLASER" || type == "RLASER" || type == "ROBOTLASER1";
}

CarmenLogReader::CarmenLogReader(const std::string& path, CarmenReaderOptions options)
    : reader_(path), options_(std::move(options)) {
  if (!options_.laser_type.empty() && !isLaserType(options_.laser_type)) {
    throw std::invalid_argument("CARMEN log '" + path + "': laser type '" + options_.laser_type +
                                "' is not one of FLASER, RLASER, ROBOTLASER1");
  }
}

void CarmenLogReader::report(const std::string& message) {
  ++malformed_;
  if (issues_.size() < kMaxIssuesKept) {
    issues_.push_back(reader_.path() + ":" + std::to_string(reader_.lineNumber()) + ": " + message);
  }
}

double CarmenLogReader::paramDouble(const std::string& key, double fallback) const {
  const auto it = params_.find(key);
  if (it == params_.end()) return fallback;
  const ParsedNumber v = parseNumber(it->second);
  // A value that is there but no number ("90deg", "nan") is not the default: the scans would
  // be read with another field of view or mounting than the log says, without a word.
  if (!v.ok() || !std::isfinite(v.value)) {
    throw std::invalid_argument("PARAM " + key + " = '" + it->second + "' is not a finite number");
  }
  return v.value;
}

bool CarmenLogReader::parseLaser(const std::string& type, const std::vector<std::string>& f,
                                 CarmenLaser& out) {
  out.type = type;
  out.line = reader_.lineNumber();
  std::optional<double> declared_fov;  // ROBOTLASER1's own field of view (rad)
  const bool front = type != "RLASER";
  const std::string side = front ? "front" : "rear";
  if (type == "ROBOTLASER1") {
    // ROBOTLASER1 laser_type start_angle fov resolution max_range accuracy remission_mode
    //   n r1..rn n_rem rem1..rem_nrem laser_x laser_y laser_theta robot_x robot_y robot_theta
    //   tv rv forward_safety side_safety turn_axis ipc_ts host logger_ts
    out.start_angle_rad = finiteNumber(f, 2, "start_angle");
    declared_fov = finiteNumber(f, 3, "field_of_view");
    out.angular_resolution_rad = finiteNumber(f, 4, "angular_resolution");
    out.max_range_m = finiteNumber(f, 5, "maximum_range");
    const std::size_t n = count(f, 8, "num_readings");
    if (f.size() < 9 + n + 1) throw std::invalid_argument("fewer ranges than num_readings = " + f[8]);
    out.ranges_m.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.ranges_m[i] = number(f, 9 + i, "range");
    const std::size_t nr = count(f, 9 + n, "num_remissions");
    const std::size_t base = 10 + n + nr;
    if (f.size() != base + 14) {
      throw std::invalid_argument(std::to_string(f.size()) + " fields, expected " +
                                  std::to_string(base + 14) + " for " + std::to_string(n) +
                                  " ranges and " + std::to_string(nr) + " remissions");
    }
    out.laser_pose = {poseNumber(f, base, "laser_x"), poseNumber(f, base + 1, "laser_y"),
                      poseNumber(f, base + 2, "laser_theta")};
    out.robot_pose = {poseNumber(f, base + 3, "robot_x"), poseNumber(f, base + 4, "robot_y"),
                      poseNumber(f, base + 5, "robot_theta")};
    out.stamp_s = stampNumber(f, base + 11, "ipc_timestamp");
    out.laser_on_robot = relative(out.laser_pose, out.robot_pose);
  } else {
    const std::size_t n = count(f, 1, "num_readings");
    if (f.size() != n + 11) {
      throw std::invalid_argument(std::to_string(f.size()) + " fields, expected " +
                                  std::to_string(n + 11) + " for num_readings = " + f[1]);
    }
    out.ranges_m.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.ranges_m[i] = number(f, 2 + i, "range");
    out.laser_pose = {poseNumber(f, n + 2, "x"), poseNumber(f, n + 3, "y"), poseNumber(f, n + 4, "theta")};
    out.robot_pose = {poseNumber(f, n + 5, "odom_x"), poseNumber(f, n + 6, "odom_y"),
                      poseNumber(f, n + 7, "odom_theta")};
    out.stamp_s = stampNumber(f, n + 8, "ipc_timestamp");
    const double fov_deg = paramDouble("laser_" + side + "_laser_fov", 180.0);
    double res_deg = paramDouble("laser_" + side + "_laser_resolution", 0.0);
    // A negative field of view or resolution would turn the beams the other way: the scan,
    // and every pose from it, mirrored.
    if (!(fov_deg > 0.0 && fov_deg <= 360.0)) {
      throw std::invalid_argument("PARAM laser_" + side + "_laser_fov = " + numberText(fov_deg) +
                                  ": a field of view in (0, 360] degrees is needed");
    }
    if (res_deg < 0.0) {
      throw std::invalid_argument("PARAM laser_" + side + "_laser_resolution = " + numberText(res_deg) +
                                  ": a resolution > 0 degrees (or 0: fov / beams) is needed");
    }
    if (!(res_deg > 0.0) && n > 1) res_deg = (n % 2 == 1) ? fov_deg / static_cast<double>(n - 1)
                                                          : fov_deg / static_cast<double>(n);
    out.angular_resolution_rad = res_deg * kDegToRad;
    out.start_angle_rad = -0.5 * fov_deg * kDegToRad;
    double max_range = paramDouble("robot_" + side + "_laser_max", 0.0);
    if (!(max_range > 0.0)) max_range = paramDouble("laser_" + side + "_laser_max_range", 0.0);
    if (!(max_range > 0.0)) max_range = options_.default_max_range_m;
    out.max_range_m = max_range;
    const double offset = paramDouble("robot_" + side + "laser_offset", 0.0);
    if (std::abs(offset) > kMaxLogCoordinate) {
      throw std::invalid_argument("PARAM robot_" + side + "laser_offset = " + numberText(offset) +
                                  " is beyond +-1e6 m: not a mounting");
    }
    out.laser_on_robot = front ? Pose2D{offset, 0.0, 0.0} : Pose2D{-offset, 0.0, kPi};
  }
  // A line no scan can be made of is malformed too: it must not decide the laser type.
  if (out.ranges_m.size() < 2) {
    throw std::invalid_argument(std::to_string(out.ranges_m.size()) + " beam(s) (need 2 or more)");
  }
  if (!std::isfinite(out.angular_resolution_rad) || out.angular_resolution_rad == 0.0) {
    throw std::invalid_argument("angular resolution " + numberText(out.angular_resolution_rad) +
                                " rad: a non-zero resolution is needed");
  }
  // The beams' span: at most a full turn (give or take one step, a 360-degree scanner's
  // first and last beams may coincide), and what a ROBOTLASER1 line says it is (give or take
  // one step: writers count the field of view over n or n - 1 steps).
  const double step = std::abs(out.angular_resolution_rad);
  const double spanned = static_cast<double>(out.ranges_m.size() - 1) * step;
  if (spanned > 2.0 * kPi + step) {
    throw std::invalid_argument(std::to_string(out.ranges_m.size()) + " beams of " + numberText(step) + " rad span " +
                                numberText(spanned) + " rad, more than a full turn");
  }
  if (declared_fov && std::abs(std::abs(*declared_fov) - spanned) > step + 1e-6) {
    throw std::invalid_argument("field of view " + numberText(*declared_fov) + " rad disagrees with " +
                                std::to_string(out.ranges_m.size()) + " beams of " + numberText(step) + " rad (" +
                                numberText(spanned) + " rad)");
  }
  if (!(out.max_range_m > 0.0)) {
    throw std::invalid_argument("maximum range " + numberText(out.max_range_m) + " m: it must be > 0");
  }
  for (double& r : out.ranges_m) {
    if (isSickErrorCode(r)) r = std::numeric_limits<double>::infinity();
  }
  return true;
}

std::optional<CarmenLaser> CarmenLogReader::next() {
  std::string line;
  while (reader_.next(line)) {
    const auto f = split(line);
    if (f.empty() || f[0][0] == '#') continue;
    const std::string& type = f[0];
    if (type == "PARAM") {
      if (f.size() >= 3) params_[f[1]] = f[2];
      else report("PARAM line with " + std::to_string(f.size()) + " fields (expected name and value)");
      continue;
    }
    if (type == "ODOM") {
      try {
        odometry_ = Pose2D{poseNumber(f, 1, "x"), poseNumber(f, 2, "y"), poseNumber(f, 3, "theta")};
      } catch (const std::invalid_argument& e) {
        report(std::string("ODOM: ") + e.what());
      }
      continue;
    }
    if (isLaserType(type)) {
      if (!options_.laser_type.empty() && type != options_.laser_type) continue;
      CarmenLaser laser;
      try {
        parseLaser(type, f, laser);
      } catch (const std::invalid_argument& e) {
        report(type + ": " + e.what() + " (line skipped)");
        continue;
      }
      // The first line that parsed decides the type, never a malformed one.
      if (options_.laser_type.empty()) options_.laser_type = type;
      return laser;
    }
    if (unreadLaserTypes().count(type) != 0) ++unread_lasers_[type];
    if (ignoredTypes().count(type) == 0) {
      // Distinct types are counted up to a bound; beyond it they share one entry.
      const bool known = unknown_.count(type) != 0 || unknown_.size() < kMaxUnknownTypes;
      ++unknown_[known ? type : std::string("(other types)")];
    }
  }
  return std::nullopt;
}

}  // namespace lidarseg::logs
