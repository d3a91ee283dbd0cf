#include "lidarseg/report/Baselines.h"

namespace lidarseg::report {

const std::vector<BaselineKind>& baselineKinds() {
  static const std::vector<BaselineKind> kinds = {
      {"icp", "MRPT ICP (keyframed)", "MRPT ICP keyframed", kIcpColour},
      {"icp-s2s", "MRPT ICP (scan to scan)", "MRPT ICP scan to scan", kIcpS2sColour},
  };
  return kinds;
}

const BaselineKind* baselineKind(std::string_view name) {
  for (const BaselineKind& k : baselineKinds()) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

}  // namespace lidarseg::report
