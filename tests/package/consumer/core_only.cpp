// The pure core through pkg-config (`pkg-config --cflags --libs lidarseg-core`): segments
// an L-shaped corner given as ranges, no MRPT.
#include <cmath>
#include <iostream>
#include <memory>
#include <vector>

#include "lidarseg/core/Scan.h"
#include "lidarseg/core/ScanSegmenter.h"

int main() {
  // Sensor at (1, 1) in the corner of the walls x = 0 and y = 0, 181 beams over 180 degrees
  // looking at (-1, -1).
  const std::size_t n = 181;
  std::vector<double> angles(n);
  lidarseg::Scan scan;
  scan.ranges_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    angles[i] = -M_PI / 2 + M_PI * static_cast<double>(i) / static_cast<double>(n - 1);
    const double a = angles[i] + 1.25 * M_PI;  // world direction of beam i
    const double tx = std::cos(a) < 0 ? 1.0 / -std::cos(a) : 1e9;
    const double ty = std::sin(a) < 0 ? 1.0 / -std::sin(a) : 1e9;
    scan.ranges_m[i] = std::min(tx, ty);
  }
  scan.layout = std::make_shared<const lidarseg::BeamLayout>(std::move(angles));
  const lidarseg::ScanSegmenter segmenter;
  const auto seg = segmenter.process(scan);
  const auto& top = seg.level(lidarseg::CascadeLevel::kFusedAgain).segments;
  std::cout << "core corner: " << top.size() << " segments\n";
  return top.size() == 2 ? 0 : 1;
}
