/// @file fuzz_config.cpp
/// libFuzzer target: any text read as a parameter file, INI (first byte even) or YAML
/// (odd), by every section loader: [segmentation], [matcher] + [odometry], [features],
/// [simulation], [camera] + [rois] + [people]. Loaded parameters must pass validation.

#include <cstdint>

#include "FuzzInput.h"
#include "lidarseg/mrpt/FeatureConfig.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/SegmentationConfig.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/mrpt/VisionConfig.h"

using namespace lidarseg;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = fuzz::writeInput(data + 1, size - 1, data[0] % 2 == 0 ? "input.ini" : "input.yaml");
  using namespace mrpt_adapter;
  // What a loader returns is what the core will run with: it must be valid (validate()
  // throws std::invalid_argument without the file's name, which requireNamed turns into a
  // finding).
  fuzz::expectNamedErrors(path, [&] { loadSegmentationParamsFile(path).validate(); });
  fuzz::expectNamedErrors(path, [&] { loadOdometryParamsFile(path).validate(); });
  fuzz::expectNamedErrors(path, [&] { loadFeatureDetectorParamsFile(path).validate(); });
  fuzz::expectNamedErrors(path, [&] {
    sim::SimulationParams p;
    loadSimulationParamsFile(p, path);
    p.validate();
  });
  fuzz::expectNamedErrors(path, [&] {
    const VisionConfig v = loadVisionConfigFile(path);
    v.rois.validate();
    v.people.validate();
    if (v.camera) v.camera->validate();
  });
  return 0;
}
