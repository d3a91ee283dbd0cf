#pragma once
/// @file WorldFile.h
/// Reading simulated worlds from text files (format: config/worlds/README.md).

#include <istream>
#include <string>

#include "lidarseg/sim/World.h"

namespace lidarseg::sim {

/// Parses a world description, one item per line (metres and degrees, `#` comments):
///
///     wall X1 Y1 X2 Y2
///     polyline X1 Y1 X2 Y2 [X3 Y3 ...]
///     door open   X1 Y1 X2 Y2
///     door closed X1 Y1 X2 Y2 RECESS_M
///     door ajar   X1 Y1 X2 Y2 ANGLE_DEG
///     pillar CX CY SIZE
///     box CX CY WIDTH DEPTH [YAW_DEG]
///
/// Doors are applied after every wall is read, so they may cut walls declared later.
/// @param source name used in error messages (usually the file's path).
/// @throws std::runtime_error "source:line: message" for an unknown keyword, a missing,
/// extra or non-numeric value, or a degenerate item (a wall of zero length, ...); for a
/// door given twice, two doors on one opening (naming both lines), a door on no wall; and
/// "source: no walls" for a world without a `wall` or `polyline`.
World parseWorld(std::istream& in, const std::string& source);

/// Reads a world file.
/// @throws std::runtime_error naming the file when it cannot be opened, or as parseWorld().
World loadWorldFile(const std::string& path);

}  // namespace lidarseg::sim
