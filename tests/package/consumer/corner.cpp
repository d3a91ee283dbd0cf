// Segments an L-shaped corner through an MRPT observation, using only the installed package.
#include <cmath>
#include <iostream>

#include <mrpt/obs/CObservation2DRangeScan.h>

#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/mrpt/ScanConverter.h"

int main() {
  // Sensor at (1, 1) in a corner made by the walls x = 0 and y = 0, looking at (-1, -1).
  mrpt::obs::CObservation2DRangeScan obs;
  const std::size_t n = 181;
  obs.aperture = static_cast<float>(M_PI);
  obs.rightToLeft = true;
  obs.maxRange = 20.0f;
  obs.resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = obs.getScanAngle(i) + 1.25 * M_PI;  // world direction of beam i
    const double tx = std::cos(a) < 0 ? 1.0 / -std::cos(a) : 1e9;
    const double ty = std::sin(a) < 0 ? 1.0 / -std::sin(a) : 1e9;
    obs.setScanRange(i, static_cast<float>(std::min(tx, ty)));
    obs.setScanRangeValidity(i, true);
  }
  lidarseg::mrpt_adapter::ScanConverter converter;
  const lidarseg::ScanSegmenter segmenter;
  const auto seg = segmenter.process(converter.convert(obs));
  const auto& top = seg.level(lidarseg::CascadeLevel::kFusedAgain).segments;
  std::cout << "corner: " << top.size() << " segments\n";
  return top.size() == 2 ? 0 : 1;
}
