#include "lidarseg/core/Feature.h"

namespace lidarseg {

const char* toString(FeatureType type) {
  switch (type) {
    case FeatureType::kDoorOpen:
      return "door_open";
    case FeatureType::kDoorClosed:
      return "door_closed";
    case FeatureType::kDoorAjar:
      return "door_ajar";
    case FeatureType::kCornerConvex:
      return "corner_convex";
    case FeatureType::kCornerConcave:
      return "corner_concave";
  }
  return "unknown";
}

std::optional<FeatureType> featureTypeFromString(const std::string& name) {
  for (std::size_t i = 0; i < kNumFeatureTypes; ++i) {
    const auto t = static_cast<FeatureType>(i);
    if (name == toString(t)) return t;
  }
  return std::nullopt;
}

}  // namespace lidarseg
