#include "lidarseg/core/Segmentation.h"

#include <stdexcept>
#include <string>

namespace lidarseg {

const char* toString(CascadeLevel level) {
  switch (level) {
    case CascadeLevel::kWallDanielsson:
      return "wall-danielsson";
    case CascadeLevel::kFused:
      return "fused";
    case CascadeLevel::kEroded:
      return "eroded";
    case CascadeLevel::kFusedAgain:
      return "fused-again";
  }
  return "unknown";
}

std::vector<Eigen::Vector2d> Segmentation::pointsOf(CascadeLevel l, std::size_t index) const {
  const SegmentLevel& lvl = level(l);
  if (index >= lvl.segments.size()) {
    throw std::out_of_range("Segmentation::pointsOf: level " + std::string(toString(l)) +
                            " has " + std::to_string(lvl.segments.size()) +
                            " segments, asked for index " + std::to_string(index));
  }
  const Segment& seg = lvl.segments[index];
  const SegmentLevel& base = levels[0];
  std::vector<Eigen::Vector2d> out;
  out.reserve(seg.num_points);
  for (std::uint32_t p = seg.parts_begin; p < seg.parts_end; ++p) {
    const Segment& part = base.segments[lvl.parts[p]];
    for (std::uint32_t beam = part.first_beam; beam <= part.last_beam; ++beam) {
      out.push_back(points[beam]);
    }
  }
  return out;
}

void Segmentation::clear() {
  points.clear();
  num_valid_beams = 0;
  wraps_around = false;
  for (auto& l : levels) l.clear();
}

}  // namespace lidarseg
