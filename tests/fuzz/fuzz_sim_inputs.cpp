/// @file fuzz_sim_inputs.cpp
/// libFuzzer target: any text read as a simulator world file (first byte even) or
/// trajectory file (odd); a world that parses is ray cast, a trajectory is sampled.

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "FuzzInput.h"
#include "lidarseg/sim/RayCaster.h"
#include "lidarseg/sim/Trajectory.h"
#include "lidarseg/sim/WorldFile.h"

using namespace lidarseg;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool world = data[0] % 2 == 0;
  const std::string path = fuzz::writeInput(data + 1, size - 1, world ? "input.world" : "input.traj");
  fuzz::expectNamedErrors(path, [&] {
    if (world) {
      const sim::World w = sim::loadWorldFile(path);
      const sim::RayCaster caster(w);
      for (int k = 0; k < 16; ++k) {
        const double a = k * M_PI / 8;
        const sim::RayHit hit = caster.cast({0.5, 0.5}, {std::cos(a), std::sin(a)}, 80.0);
        fuzz::require(!hit.hit() || (hit.range >= 0.0 && hit.range <= 80.0), "a hit is within the range");
      }
    } else {
      const sim::Trajectory t = sim::loadTrajectoryFile(path);
      fuzz::require(std::isfinite(t.length()) && t.length() > 0.0, "a trajectory has a finite length");
      for (int k = 0; k <= 8; ++k) {
        const auto p = t.poseAt(t.duration() * k / 8.0);
        fuzz::require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw), "poses are finite");
      }
    }
  });
  return 0;
}
