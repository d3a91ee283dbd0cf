#include "lidarseg/mrpt/ScanConverter.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <mrpt/core/Clock.h>

namespace lidarseg::mrpt_adapter {

std::shared_ptr<const BeamLayout> ScanConverter::layoutFor(std::size_t num_beams,
                                                           double aperture_rad,
                                                           bool right_to_left) {
  const auto key = std::make_tuple(num_beams, aperture_rad, right_to_left);
  auto it = layouts_.find(key);
  if (it != layouts_.end()) return it->second;
  const double step = aperture_rad / static_cast<double>(num_beams - 1);
  auto layout = std::make_shared<const BeamLayout>(
      right_to_left ? BeamLayout::uniform(num_beams, -0.5 * aperture_rad, step)
                    : BeamLayout::uniform(num_beams, 0.5 * aperture_rad, -step));
  layouts_.emplace(key, layout);
  return layout;
}

Scan ScanConverter::convert(const mrpt::obs::CObservation2DRangeScan& obs) {
  const std::size_t n = obs.getScanSize();
  if (n < 2) {
    throw std::invalid_argument("CObservation2DRangeScan '" + obs.sensorLabel + "' has " +
                                std::to_string(n) + " beams; at least 2 are needed");
  }
  if (!std::isfinite(obs.aperture) || obs.aperture <= 0.0f) {
    throw std::invalid_argument("CObservation2DRangeScan '" + obs.sensorLabel +
                                "' has an invalid aperture (" + std::to_string(obs.aperture) +
                                " rad)");
  }
  Scan scan;
  scan.layout = layoutFor(n, static_cast<double>(obs.aperture), obs.rightToLeft);
  scan.ranges_m.resize(n);
  scan.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    scan.ranges_m[i] = static_cast<double>(obs.getScanRange(i));
    scan.valid[i] = obs.getScanRangeValidity(i) ? 1 : 0;
  }
  scan.stamp_s = mrpt::Clock::toDouble(obs.timestamp);
  scan.min_range_m = min_range_m_;
  scan.max_range_m = static_cast<double>(obs.maxRange);
  return scan;
}

}  // namespace lidarseg::mrpt_adapter
