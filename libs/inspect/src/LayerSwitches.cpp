#include "lidarseg/inspect/LayerSwitches.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "lidarseg/eval/Csv.h"

namespace lidarseg::inspect {

namespace {

// A layer: its name in --layers, the window key that shows or hides it, and its flag.
struct LayerSwitch {
  const char* name;
  int key;
  bool& (*flag)(Layers&);
};
const LayerSwitch kLayerSwitches[] = {
    {"raw", 'R', [](Layers& l) -> bool& { return l.raw_points; }},
    {"l0", 'Z', [](Layers& l) -> bool& { return l.levels[0]; }},
    {"l1", 'X', [](Layers& l) -> bool& { return l.levels[1]; }},
    {"l2", 'C', [](Layers& l) -> bool& { return l.levels[2]; }},
    {"l3", 'V', [](Layers& l) -> bool& { return l.levels[3]; }},
    {"indices", 'I', [](Layers& l) -> bool& { return l.indices; }},
    {"predicted", 'K', [](Layers& l) -> bool& { return l.predicted; }},
    {"matches", 'M', [](Layers& l) -> bool& { return l.matches; }},
    {"features", 'F', [](Layers& l) -> bool& { return l.features; }},
    {"trajectory", 'O', [](Layers& l) -> bool& { return l.trajectory; }},
    {"camera", 'A', [](Layers& l) -> bool& { return l.camera; }},
};

// Every layer on, or every layer off.
Layers allLayers(bool on) {
  Layers l;
  for (const LayerSwitch& s : kLayerSwitches) s.flag(l) = on;
  return l;
}

}  // namespace

Layers parseLayers(const std::string& list) {
  if (list.empty()) return Layers{};
  Layers l = allLayers(false);
  for (const std::string& name : eval::splitCsvLine(list)) {
    if (name == "all") {
      l = allLayers(true);
      continue;
    }
    const auto s = std::find_if(std::begin(kLayerSwitches), std::end(kLayerSwitches),
                                [&](const LayerSwitch& x) { return name == x.name; });
    if (s == std::end(kLayerSwitches)) {
      throw std::invalid_argument("--layers: unknown layer '" + name +
                                  "' (raw, l0, l1, l2, l3, indices, predicted, matches, features, "
                                  "trajectory, camera, all)");
    }
    s->flag(l) = true;
  }
  return l;
}

bool toggleLayer(Layers& layers, int key) {
  for (const LayerSwitch& s : kLayerSwitches) {
    if (s.key != key) continue;
    s.flag(layers) = !s.flag(layers);
    return true;
  }
  return false;
}

}  // namespace lidarseg::inspect
