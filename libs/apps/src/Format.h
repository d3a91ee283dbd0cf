#pragma once
// Private to lidarseg::apps: number formatting of the reports.

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace lidarseg::apps {

/// `v` with `digits` decimals, "n/a" when not finite.
inline std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

}  // namespace lidarseg::apps
