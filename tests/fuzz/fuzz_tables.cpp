/// @file fuzz_tables.cpp
/// libFuzzer target: any text read as one of the tables the apps take beside a log (the
/// first byte chooses): a TUM trajectory (ground truth or --trajectory), a Freiburg
/// relations file, a true-features CSV of the simulator, a regions-of-interest CSV of
/// lidarseg-people.

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "FuzzInput.h"
#include "lidarseg/vision/RegionTable.h"
#include "lidarseg/eval/FeatureEvaluation.h"
#include "lidarseg/eval/Relations.h"
#include "lidarseg/eval/StampedTrajectory.h"

using namespace lidarseg;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int kind = data[0] % 4;
  const char* names[4] = {"input.tum", "input.relations", "input.features.csv", "input.rois.csv"};
  const std::string path = fuzz::writeInput(data + 1, size - 1, names[kind]);
  fuzz::expectNamedErrors(path, [&] {
    switch (kind) {
      case 0: {
        const eval::StampedTrajectory t = eval::readTum(path);
        for (const auto& p : t) {
          fuzz::require(std::isfinite(p.stamp_s) && std::isfinite(p.pose.x) && std::isfinite(p.pose.y) &&
                            std::isfinite(p.pose.yaw),
                        "TUM poses are finite");
        }
        break;
      }
      case 1: {
        for (const auto& r : eval::readRelations(path)) {
          fuzz::require(std::isfinite(r.t1_s) && std::isfinite(r.t2_s) && std::isfinite(r.delta.x), "relations are finite");
        }
        break;
      }
      case 2:
        eval::readTrueFeatures(path);
        break;
      default: {
        vision::RegionTable table;
        table.read(path);
        for (const auto& r : table.of(0, "a.png")) fuzz::require(r.width > 0 && r.height > 0, "regions are not empty");
        break;
      }
    }
  });
  return 0;
}
