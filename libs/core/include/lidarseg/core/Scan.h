#pragma once
/// @file Scan.h
/// One sweep of a planar range sensor, as the core library sees it.

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "lidarseg/core/BeamLayout.h"

namespace lidarseg {

/// Ranges at or beyond this are never valid (m), whatever the sensor's maximum: no 2D
/// lidar measures a kilometre, and squaring such values would overflow the line fits.
inline constexpr double kMaxPhysicalRangeM = 1e5;
/// Ranges at or below this are never valid (m), whatever the sensor's minimum: no 2D lidar
/// measures a millimetre, and the fits weigh points by 1 / range^2 (a denormal range made
/// that infinite: found by fuzzing, docs/reliability.md).
inline constexpr double kMinPhysicalRangeM = 1e-3;

/// Which beam's instant a driver stamps a scan with (drivers differ: first, middle or last).
enum class ScanStamp : std::size_t {
  kFirst = 0,   ///< the first beam's time
  kMiddle = 1,  ///< the middle of the sweep
  kLast = 2,    ///< the last beam's time
};
/// "first", "middle", "last".
const char* toString(ScanStamp s);
/// The convention of that name. @throws std::invalid_argument listing the names.
ScanStamp scanStampFromString(const std::string& name);

/// One sweep of a 2D range sensor: ordered beams in the sensor frame.
///
/// A beam is valid when its range is finite, strictly greater than min_range_m and than
/// kMinPhysicalRangeM,
/// strictly less than max_range_m (a return at the maximum range means "no echo") and
/// than kMaxPhysicalRangeM, and
/// its entry of `valid` (when given) is non-zero. Invalid beams break segments (paper II.A).
struct Scan {
  /// Beam directions; shared by every scan of one sensor. Required.
  std::shared_ptr<const BeamLayout> layout;
  /// Measured range of each beam (m); same size as the layout.
  std::vector<double> ranges_m;
  /// Optional per-beam validity flags from the driver (0 = invalid); empty means
  /// "decide from the range alone", otherwise same size as ranges_m.
  std::vector<std::uint8_t> valid;
  /// Optional time of each beam relative to stamp_s (s), for rolling-shutter correction;
  /// empty means all beams were measured at stamp_s, otherwise same size as ranges_m.
  std::vector<double> time_offsets_s;
  /// Time of the scan (s, any epoch).
  double stamp_s = 0.0;
  /// Ranges at or below this are invalid (m).
  double min_range_m = 0.0;
  /// Ranges at or above this are invalid (m): the sensor's "no return".
  double max_range_m = std::numeric_limits<double>::infinity();

  std::size_t size() const { return ranges_m.size(); }

  /// Whether beam i holds a usable range (see the class comment). No bounds check.
  bool beamValid(std::size_t i) const {
    const double r = ranges_m[i];
    // NaN fails every comparison, so it is rejected here too.
    const bool in_range = r > min_range_m && r > kMinPhysicalRangeM && r < max_range_m && r < kMaxPhysicalRangeM;
    return in_range && (valid.empty() || valid[i] != 0);
  }

  /// Checks that the arrays are consistent with the layout and the limits are sane.
  /// @throws std::invalid_argument naming the offending field and both sizes.
  void validate() const;
};

}  // namespace lidarseg
