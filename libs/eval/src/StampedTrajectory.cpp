#include "lidarseg/eval/StampedTrajectory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace lidarseg::eval {

StampedTrajectory readTum(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open trajectory '" + path + "'");
  StampedTrajectory out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    std::size_t count = 0;
    std::string token;
    while (fields >> token) {
      if (count == 8) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) +
                                 ": more than 8 fields (expected 'timestamp x y z qx qy qz qw')");
      }
      char* end = nullptr;
      v[count] = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(v[count])) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": field " +
                                 std::to_string(count + 1) + " '" + token + "' is not a finite number");
      }
      ++count;
    }
    if (count != 8) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + std::to_string(count) +
                               " fields (expected 8: 'timestamp x y z qx qy qz qw')");
    }
    if (!out.empty() && v[0] < out.back().stamp_s) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": timestamp " + token +
                               " goes back in time");
    }
    const double qx = v[4], qy = v[5], qz = v[6], qw = v[7];
    const double yaw = std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
    out.push_back({v[0], {v[1], v[2], yaw}});
  }
  return out;
}

void writeTum(std::ostream& os, const StampedTrajectory& trajectory, const std::string& header) {
  if (!header.empty()) os << "# " << header << "\n";
  os << std::fixed;
  for (const auto& p : trajectory) {
    const double half = 0.5 * p.pose.yaw;
    os << std::setprecision(9) << p.stamp_s << ' ' << p.pose.x << ' ' << p.pose.y << " 0 0 0 "
       << std::sin(half) << ' ' << std::cos(half) << '\n';
  }
}

std::optional<std::size_t> nearestIndex(const StampedTrajectory& trajectory, double stamp_s,
                                        double tolerance_s) {
  if (trajectory.empty()) return std::nullopt;
  const auto it = std::lower_bound(trajectory.begin(), trajectory.end(), stamp_s,
                                   [](const StampedPose& p, double t) { return p.stamp_s < t; });
  std::size_t best = static_cast<std::size_t>(it - trajectory.begin());
  if (best == trajectory.size()) best = trajectory.size() - 1;
  if (best > 0 && std::abs(trajectory[best - 1].stamp_s - stamp_s) <=
                      std::abs(trajectory[best].stamp_s - stamp_s)) {
    --best;
  }
  if (std::abs(trajectory[best].stamp_s - stamp_s) > tolerance_s) return std::nullopt;
  return best;
}

double pathLength(const StampedTrajectory& trajectory) {
  double length = 0.0;
  for (std::size_t k = 1; k < trajectory.size(); ++k) {
    length += std::hypot(trajectory[k].pose.x - trajectory[k - 1].pose.x,
                         trajectory[k].pose.y - trajectory[k - 1].pose.y);
  }
  return length;
}

}  // namespace lidarseg::eval
