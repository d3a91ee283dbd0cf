#pragma once
/// @file ScanConverter.h
/// MRPT laser observations to core scans.

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include <mrpt/obs/CObservation2DRangeScan.h>

#include "lidarseg/core/BeamLayout.h"
#include "lidarseg/core/Scan.h"

namespace lidarseg::mrpt_adapter {

/// Converts `mrpt::obs::CObservation2DRangeScan` to lidarseg::Scan, in the sensor frame.
///
/// Beam i's angle follows MRPT's convention (`getScanAngle()`): evenly spaced over the
/// aperture, centred on the sensor's x axis, counter-clockwise when `rightToLeft`.
/// Validity comes from the observation's per-beam flags and its `maxRange`.
/// Beam layouts are cached per (beams, aperture, direction), so a sensor's cosines and
/// sines are computed once for the whole log.
class ScanConverter {
 public:
  /// Ranges at or below this are treated as invalid (m).
  explicit ScanConverter(double min_range_m = 0.0) : min_range_m_(min_range_m) {}

  /// @throws std::invalid_argument if the observation has fewer than 2 beams or a
  /// non-finite aperture.
  Scan convert(const mrpt::obs::CObservation2DRangeScan& obs);

  /// Layouts kept at most (one per beam count, aperture and direction met).
  static constexpr std::size_t kMaxCachedLayouts = CentredLayoutCache::kMaxLayouts;
  /// The layout for a sensor with this geometry (cached).
  std::shared_ptr<const BeamLayout> layoutFor(std::size_t num_beams, double aperture_rad,
                                              bool right_to_left);

 private:
  double min_range_m_;
  CentredLayoutCache layouts_;
};

/// The MRPT observation of a core scan (the inverse of ScanConverter::convert()).
/// The layout must be evenly spaced and centred on the sensor's x axis, as MRPT's
/// observations are (aperture + direction); invalid beams are flagged invalid.
/// @throws std::invalid_argument otherwise.
mrpt::obs::CObservation2DRangeScan::Ptr makeRangeScanObservation(
    const Scan& scan, const std::string& sensor_label, const mrpt::poses::CPose3D& sensor_pose,
    double range_sigma_m);

}  // namespace lidarseg::mrpt_adapter
