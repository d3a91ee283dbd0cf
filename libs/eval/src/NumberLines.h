#pragma once
// Private to lidarseg::eval: reading text files of eight numbers per line (TUM
// trajectories, Freiburg relations).

#include <array>
#include <cstddef>
#include <functional>
#include <string>

namespace lidarseg::eval::detail {

/// Calls `visit(line_number, values)` for each data line of `path` (blank lines and `#`
/// comments skipped).
/// @param kind what the file is, for messages ("trajectory", "relations")
/// @param format the expected fields, for messages ("timestamp x y z qx qy qz qw")
/// @param stamps how many leading fields are stamps (s; finite, not bounded)
/// @throws std::runtime_error naming the file and line for an unreadable file or a line
/// without exactly 8 finite numbers, or with a field after the stamps beyond
/// +-kMaxLogCoordinate (and whatever `visit` throws).
void forEachLineOf8Numbers(const std::string& path, const std::string& kind, const std::string& format,
                           std::size_t stamps, const std::function<void(std::size_t, const std::array<double, 8>&)>& visit);

}  // namespace lidarseg::eval::detail
