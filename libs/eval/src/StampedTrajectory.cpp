#include "lidarseg/eval/StampedTrajectory.h"

#include "NumberLines.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace lidarseg::eval {

namespace {
// The norms of a TUM line's quaternion taken as a rotation (normalised), decision 108.
constexpr double kMinQuaternionNorm = 0.9;
constexpr double kMaxQuaternionNorm = 1.1;
}  // namespace

StampedTrajectory readTum(const std::string& path) {
  StampedTrajectory out;
  detail::forEachLineOf8Numbers(path, "trajectory", "timestamp x y z qx qy qz qw", 1,
                                [&](std::size_t line, const std::array<double, 8>& v) {
    if (!out.empty() && v[0] < out.back().stamp_s) {
      std::ostringstream stamp;
      stamp << std::setprecision(17) << v[0];
      throw std::runtime_error(path + ":" + std::to_string(line) + ": timestamp " + stamp.str() +
                               " goes back in time");
    }
    // Decision 108: a unit quaternion as written (to ~1e-6, or a few digits) is normalised;
    // one of norm outside [0.9, 1.1] (zero, doubled) is no rotation the file meant.
    const double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (!(norm >= kMinQuaternionNorm && norm <= kMaxQuaternionNorm)) {
      std::ostringstream shown;
      shown << std::setprecision(6) << norm;  // six digits: 1.10001 is not shown as 1.1
      throw std::runtime_error(path + ":" + std::to_string(line) + ": not a unit quaternion (norm " + shown.str() +
                               "; qx qy qz qw must have a norm from 0.9 to 1.1)");
    }
    const double qx = v[4] / norm, qy = v[5] / norm, qz = v[6] / norm, qw = v[7] / norm;
    const double yaw = std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
    out.push_back({v[0], {v[1], v[2], yaw}});
  });
  return out;
}

namespace {
// v as written with 9 decimals, without a "-0.000000000" for what rounds to zero.
double noNegativeZero(double v) { return std::abs(v) < 5e-10 ? 0.0 : v; }
}  // namespace

void writeTum(std::ostream& os, const StampedTrajectory& trajectory, const std::string& header) {
  if (!header.empty()) os << "# " << header << "\n";
  os << std::fixed;
  for (const auto& p : trajectory) {
    const double half = 0.5 * p.pose.yaw;
    os << std::setprecision(9) << p.stamp_s << ' ' << noNegativeZero(p.pose.x) << ' ' << noNegativeZero(p.pose.y)
       << " 0 0 0 " << noNegativeZero(std::sin(half)) << ' ' << std::cos(half) << '\n';
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
