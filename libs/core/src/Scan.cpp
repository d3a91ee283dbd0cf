#include "lidarseg/core/Scan.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace lidarseg {

const char* toString(ScanStamp s) {
  switch (s) {
    case ScanStamp::kFirst:
      return "first";
    case ScanStamp::kMiddle:
      return "middle";
    case ScanStamp::kLast:
      return "last";
  }
  return "unknown";
}

ScanStamp scanStampFromString(const std::string& name) {
  if (name == "first") return ScanStamp::kFirst;
  if (name == "middle") return ScanStamp::kMiddle;
  if (name == "last") return ScanStamp::kLast;
  throw std::invalid_argument("scan stamp '" + name + "' is not one of first, middle, last");
}

void Scan::validate() const {
  if (!layout) throw std::invalid_argument("Scan: no beam layout");
  const std::string n_layout = std::to_string(layout->size());
  if (ranges_m.size() != layout->size()) {
    throw std::invalid_argument("Scan: ranges_m has " + std::to_string(ranges_m.size()) +
                                " entries but the beam layout has " + n_layout);
  }
  if (!valid.empty() && valid.size() != ranges_m.size()) {
    throw std::invalid_argument("Scan: valid has " + std::to_string(valid.size()) +
                                " entries but ranges_m has " + std::to_string(ranges_m.size()));
  }
  if (!time_offsets_s.empty() && time_offsets_s.size() != ranges_m.size()) {
    throw std::invalid_argument("Scan: time_offsets_s has " +
                                std::to_string(time_offsets_s.size()) +
                                " entries but ranges_m has " + std::to_string(ranges_m.size()));
  }
  if (!(std::isfinite(min_range_m) && min_range_m >= 0.0)) {
    throw std::invalid_argument("Scan: min_range_m must be finite and >= 0 (got " +
                                std::to_string(min_range_m) + ")");
  }
  if (!(max_range_m > min_range_m)) {
    throw std::invalid_argument("Scan: max_range_m (" + std::to_string(max_range_m) +
                                ") must be greater than min_range_m (" +
                                std::to_string(min_range_m) + ")");
  }
}

}  // namespace lidarseg
