#pragma once
/// @file
/// lidarseg::report: the JSON outputs' conventions, on nlohmann-json: keys in the
/// order written, non-finite numbers as null, one-space indentation and a final newline.

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "lidarseg/core/WarningTally.h"

namespace lidarseg::report {

using Json = nlohmann::ordered_json;

/// A number, or null when it is not finite.
inline Json finiteOrNull(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

/// A run's warnings per kind, counted in full: [{"kind", "count", "first"}, ...] (at most
/// WarningTally::kMaxKinds + 1 entries; "(other kinds)" last).
inline Json warningKindsJson(const WarningTally& tally) {
  Json out = Json::array();
  for (const WarningTally::Kind& k : tally.kinds()) out.push_back(Json{{"kind", k.kind}, {"count", k.count}, {"first", k.first}});
  return out;
}

/// The text of a JSON output file.
inline std::string jsonText(const Json& j) { return j.dump(1) + "\n"; }

}  // namespace lidarseg::report
