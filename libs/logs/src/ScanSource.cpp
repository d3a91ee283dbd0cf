#include "lidarseg/logs/ScanSource.h"

#include <cmath>

namespace lidarseg::logs {

namespace {
constexpr std::size_t kListed = 100;  // messages kept per list; the counts stay whole
}  // namespace

bool ScanSource::Geometry::same(const Geometry& o) const {
  const double dyaw = std::remainder(yaw - o.yaw, 2.0 * 3.14159265358979323846);
  return beams == o.beams && first_angle == o.first_angle && last_angle == o.last_angle &&
         std::hypot(x - o.x, y - o.y) <= kMountingToleranceM && std::abs(dyaw) <= kMountingToleranceRad;
}

std::optional<ScanRecord> ScanSource::next() {
  std::optional<ScanRecord> r = read();
  if (!r) return r;
  watch(*r);
  r->index = returned_++;
  return r;
}

void ScanSource::watch(ScanRecord& r) {
  if (r.odometry && !(std::isfinite(r.odometry->x) && std::isfinite(r.odometry->y) && std::isfinite(r.odometry->yaw))) {
    warn(r.where + ": wheel odometry is not finite; not used");
    r.odometry.reset();
  }
  const BeamLayout& layout = *r.scan.layout;
  const Geometry g{layout.size(), layout.angle(0), layout.angle(layout.size() - 1), r.sensor_on_robot.x,
                   r.sensor_on_robot.y, r.sensor_on_robot.yaw};
  if (!geometry_) {
    geometry_ = g;
  } else if (!geometry_changed_ && !g.same(*geometry_)) {
    geometry_changed_ = true;
    warn(r.where + ": the laser '" + r.sensor + "' changes its beam count, aperture or mounting (" +
         std::to_string(geometry_->beams) + " -> " + std::to_string(g.beams) + " beams); each scan is taken as it is");
  }
}

void ScanSource::note(const std::string& message) {
  ++skipped_;
  if (issues_.size() < kListed) issues_.push_back(message);
}

void ScanSource::warn(const std::string& message) {
  if (warnings_.size() < kListed) warnings_.push_back(message);
  tally_.add(message);
}

std::vector<std::string> ScanSource::warnings() const {
  std::vector<std::string> out = warnings_;
  for (std::string& m : sourceWarnings()) out.push_back(std::move(m));
  return out;
}

WarningTally ScanSource::warningTally() const {
  WarningTally out = tally_;
  out.merge(sourceWarningTally());
  for (const auto& m : unknownTypes()) out.add(m);
  return out;
}

}  // namespace lidarseg::logs
