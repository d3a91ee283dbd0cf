#pragma once
/// @file NumberText.h
/// Numbers in messages: the value as a user would type it.

#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

namespace lidarseg {

/// The shortest text (at least 6 significant digits tried first, `%g`-like) that reads back
/// as exactly `v`: -1 gives "-1", 0.3 "0.3", 1e+15 "1e+15"; "nan", "inf" and "-inf" for
/// the non-finite values. For error messages, where std::to_string's six fixed
/// decimals turn 1e-9 into "0.000000" and 1e15 + 0.5 into "1000000000000000.500000".
inline std::string numberText(double v) {
  for (int digits = 6; digits <= std::numeric_limits<double>::max_digits10; ++digits) {
    std::ostringstream os;
    os << std::setprecision(digits) << v;
    if (v != v || std::strtod(os.str().c_str(), nullptr) == v) return os.str();
  }
  std::ostringstream os;
  os << std::setprecision(std::numeric_limits<double>::max_digits10) << v;
  return os.str();
}

}  // namespace lidarseg
