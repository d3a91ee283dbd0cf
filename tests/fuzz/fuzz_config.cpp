/// @file fuzz_config.cpp
/// libFuzzer target: any text read as a parameter file, INI (first byte even) or YAML
/// (odd), by every section loader: [segmentation], [matcher] + [odometry], [features],
/// [simulation], [camera] + [rois] + [people]. Loaded parameters must pass validation.

#include <cstdint>
#include <stdexcept>

#include "FuzzInput.h"
#include "lidarseg/mrpt/FeatureConfig.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/SegmentationConfig.h"
#include "lidarseg/mrpt/SimulationConfig.h"
#include "lidarseg/mrpt/VisionConfig.h"

using namespace lidarseg;

namespace {

template <typename Load>
void attempt(const std::string& path, Load load) {
  try {
    load();
  } catch (const std::runtime_error& e) {
    fuzz::requireNamed(e, path);
  } catch (const std::invalid_argument& e) {
    fuzz::requireNamed(e, path);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = fuzz::writeInput(data + 1, size - 1, data[0] % 2 == 0 ? "input.ini" : "input.yaml");
  using namespace mrpt_adapter;
  // What a loader returns is what the core will run with: it must be valid (validate()
  // throws std::invalid_argument without the file's name, which requireNamed turns into a
  // finding).
  attempt(path, [&] { loadSegmentationParamsFile(path).validate(); });
  attempt(path, [&] { loadOdometryParamsFile(path).validate(); });
  attempt(path, [&] { loadFeatureDetectorParamsFile(path).validate(); });
  attempt(path, [&] {
    sim::SimulationParams p;
    loadSimulationParamsFile(p, path);
    p.validate();
  });
  attempt(path, [&] {
    const VisionConfig v = loadVisionConfigFile(path);
    v.rois.validate();
    v.people.validate();
    if (v.camera) v.camera->validate();
  });
  return 0;
}
