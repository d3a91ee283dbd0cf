#pragma once
/// @file
/// lidarseg::pipeline: the JSON outputs' conventions, on nlohmann-json: keys in the
/// order written, non-finite numbers as null, one-space indentation and a final newline.

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace lidarseg::pipeline {

using Json = nlohmann::ordered_json;

/// A number, or null when it is not finite.
inline Json finiteOrNull(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

/// The text of a JSON output file.
inline std::string jsonText(const Json& j) { return j.dump(1) + "\n"; }

}  // namespace lidarseg::pipeline
