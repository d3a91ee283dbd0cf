#pragma once
/// @file LayerSwitches.h
/// The inspector's layers by name (`--layers raw,l1,l3`) and by window key (r z x c v i k m
/// f o a), one table for both.

#include <string>

#include "lidarseg/inspect/Session.h"

namespace lidarseg::inspect {

/// The layers named in a comma list of raw, l0, l1, l2, l3, indices, predicted, matches,
/// features, trajectory, camera and all; an empty list gives the default Layers.
/// @throws std::invalid_argument naming an unknown layer.
Layers parseLayers(const std::string& list);

/// Shows or hides the layer of window key `key` (upper case: 'R', 'Z', ...).
/// @return false when `key` switches no layer (`layers` unchanged).
bool toggleLayer(Layers& layers, int key);

}  // namespace lidarseg::inspect
