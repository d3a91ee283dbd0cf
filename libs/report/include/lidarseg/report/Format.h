#pragma once
/// @file
/// lidarseg::report: number formatting of the reports.

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace lidarseg::report {

/// `v` with `digits` decimals, "n/a" when not finite.
inline std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

/// Text made safe inside XML/HTML elements and attribute values.
inline std::string escapeXml(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace lidarseg::report
