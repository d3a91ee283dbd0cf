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

// A standard deviation in metres: no sensor or model of a building is uncertain by more
// than this, and its square (a variance) stays far from overflow in every sum of them.
constexpr double kMaxSigmaM = 1e3;
// A standard deviation of an angle (rad): beyond a half turn it says nothing.
constexpr double kMaxSigmaRad = 3.14159265358979323846;

inline void requireSigmaM(const std::string& key, double value, bool zero_allowed) {
  if (!(std::isfinite(value) && (zero_allowed ? value >= 0.0 : value > 0.0) && value <= kMaxSigmaM)) {
    failKey(key, std::string(zero_allowed ? "in [0, " : "in (0, ") + numberText(kMaxSigmaM) + "] m", value);
  }
}

inline void requireSigmaRad(const std::string& key, double value, bool zero_allowed) {
  if (!(std::isfinite(value) && (zero_allowed ? value >= 0.0 : value > 0.0) && value <= kMaxSigmaRad)) {
    failKey(key, std::string(zero_allowed ? "in [0, " : "in (0, ") + "pi] rad", value);
  }
}

}  // namespace lidarseg::detail
