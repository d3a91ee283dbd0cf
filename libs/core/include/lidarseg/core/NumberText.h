#pragma once
/// @file NumberText.h
/// Numbers as text: reading the numbers of logs, configs, worlds and tables
/// (`parseNumber`), and writing a value in a message as a user would type it (`numberText`).

#include <charconv>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

namespace lidarseg {

/// What `parseNumber` made of a text.
struct ParsedNumber {
  /// `ok`: the whole text is a decimal number; `not_a_number`: it is not (empty, trailing
  /// characters, hexadecimal); `out_of_range`: a decimal number whose magnitude a double
  /// cannot hold (beyond 1.8e308, or nonzero and below 2.2e-308).
  enum class Status { ok, not_a_number, out_of_range };
  Status status = Status::not_a_number;
  /// The value when `ok` (inf and nan for "inf" and "nan"); when `out_of_range`, what
  /// `strtod` would give (+-inf, 0 or a subnormal); 0 when `not_a_number`.
  double value = 0.0;
  bool ok() const { return status == Status::ok; }
};

/// Reads the whole of `text` as a decimal number, as the project's logs, configs, worlds,
/// trajectories and tables write them: an optional sign, digits with an optional point,
/// an optional exponent (`-1.5e-3`, `+2`, `.5`), or `inf` / `nan`. Unlike `strtod`, it
/// takes no hexadecimal float (`0x1p0`, which no log format writes and which a fuzzed or
/// corrupted field turns into a plausible value), no leading or trailing space, and does
/// not depend on the C locale's decimal point.
inline ParsedNumber parseNumber(std::string_view text) {
  const char* first = text.data();
  const char* const last = text.data() + text.size();
  // std::from_chars takes no '+'; a sign after it ("+-1") stays an error.
  if (first != last && *first == '+' && last - first > 1 && first[1] != '-' && first[1] != '+') ++first;
  double v = 0.0;
  const auto [end, error] = std::from_chars(first, last, v, std::chars_format::general);
  if (first == last || end != last) return {ParsedNumber::Status::not_a_number, 0.0};
  if (error == std::errc::result_out_of_range) {
    // The text is a well-formed decimal number: strtod reads it the same way.
    return {ParsedNumber::Status::out_of_range, std::strtod(std::string(first, last).c_str(), nullptr)};
  }
  if (error != std::errc()) return {ParsedNumber::Status::not_a_number, 0.0};
  return {ParsedNumber::Status::ok, v};
}

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
