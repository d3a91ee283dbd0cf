#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/core/NumberText.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <mrpt/core/Clock.h>

namespace lidarseg::mrpt_adapter {

std::shared_ptr<const BeamLayout> ScanConverter::layoutFor(std::size_t num_beams,
                                                           double aperture_rad,
                                                           bool right_to_left) {
  return layouts_.get(num_beams, aperture_rad, right_to_left);
}

Scan ScanConverter::convert(const mrpt::obs::CObservation2DRangeScan& obs) {
  const std::size_t n = obs.getScanSize();
  if (n < 2) {
    throw std::invalid_argument("CObservation2DRangeScan '" + obs.sensorLabel + "' has " +
                                std::to_string(n) + " beams; at least 2 are needed");
  }
  if (!std::isfinite(obs.aperture) || obs.aperture <= 0.0f) {
    throw std::invalid_argument("CObservation2DRangeScan '" + obs.sensorLabel +
                                "' has an invalid aperture (" + numberText(static_cast<double>(obs.aperture)) +
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

mrpt::obs::CObservation2DRangeScan::Ptr makeRangeScanObservation(
    const Scan& scan, const std::string& sensor_label, const mrpt::poses::CPose3D& sensor_pose,
    double range_sigma_m) {
  scan.validate();
  const BeamLayout& layout = *scan.layout;
  const std::size_t n = layout.size();
  if (n < 2) throw std::invalid_argument("makeRangeScanObservation: needs at least 2 beams");
  const double first = layout.angle(0), last = layout.angle(n - 1);
  const double step = (last - first) / static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(layout.angle(i) - (first + step * static_cast<double>(i))) > 1e-9 ||
        std::abs(first + last) > 1e-9) {
      throw std::invalid_argument(
          "makeRangeScanObservation: MRPT needs evenly spaced beams centred on x (beam " +
          std::to_string(i) + ")");
    }
  }
  auto obs = mrpt::obs::CObservation2DRangeScan::Create();
  obs->sensorLabel = sensor_label;
  obs->timestamp = mrpt::Clock::fromDouble(scan.stamp_s);
  obs->aperture = static_cast<float>(std::abs(last - first));
  obs->rightToLeft = step > 0.0;
  obs->maxRange = static_cast<float>(std::isfinite(scan.max_range_m) ? scan.max_range_m : 1e6);
  obs->stdError = static_cast<float>(range_sigma_m);
  obs->sensorPose = sensor_pose;
  obs->resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    obs->setScanRange(i, static_cast<float>(scan.ranges_m[i]));
    obs->setScanRangeValidity(i, scan.beamValid(i));
  }
  return obs;
}

}  // namespace lidarseg::mrpt_adapter
