#pragma once
// Private helpers for the parameter structs' validate(): each failure names the key as it
// appears in the configuration files, and the offending value.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "lidarseg/core/NumberText.h"

namespace lidarseg::detail {

[[noreturn]] inline void failKey(const std::string& key, const std::string& requirement,
                                 double value) {
  std::ostringstream os;
  os << key << " must be " << requirement << " (got " << numberText(value) << ")";
  throw std::invalid_argument(os.str());
}

inline void requirePositive(const std::string& key, double value) {
  if (!(std::isfinite(value) && value > 0.0)) failKey(key, "finite and > 0", value);
}

inline void requireNonNegative(const std::string& key, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) failKey(key, "finite and >= 0", value);
}

inline void requireInRange(const std::string& key, double value, double lo, double hi) {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    failKey(key, "in [" + numberText(lo) + ", " + numberText(hi) + "]", value);
  }
}

}  // namespace lidarseg::detail
