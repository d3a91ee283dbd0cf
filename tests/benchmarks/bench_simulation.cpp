// Simulation speed: 541-beam (LMS100) and 1081-beam (UTM-30LX) scans of the shipped worlds,
// from a sensor moving along the corridors (rolling shutter on). Target: >= 20,000
// LMS100 scans per second on one core (docs/performance.md).
#include <string>

#include <benchmark/benchmark.h>

#include "lidarseg/sim/ScanSimulator.h"
#include "lidarseg/sim/WorldFile.h"

namespace {
using namespace lidarseg::sim;

World worldNamed(const std::string& name) {
  return loadWorldFile(std::string(LIDARSEG_CONFIG_DIR) + "/worlds/" + name + ".world");
}

void runSimulation(benchmark::State& state, const World& world, SensorModel sensor) {
  ScanSimulator sim(world, sensor, 1);
  const double dt = sim.sweepDuration();
  double x = 1.0;
  for (auto _ : state) {
    // Along the bottom corridor of both worlds (y = 0), 1 m/s, back and forth.
    const lidarseg::Pose2D first{x, 0.0, 0.1};
    const lidarseg::Pose2D last{x + dt, 0.0, 0.1 + 0.5 * dt};
    benchmark::DoNotOptimize(sim.scan(first, last).ranges_m.data());
    x = x > 25.0 ? 1.0 : x + 0.02;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}

void BM_SimulateHospitalLms100(benchmark::State& state) {
  runSimulation(state, worldNamed("hospital"), SensorModel::lms100());
}
void BM_SimulateMazeLms100(benchmark::State& state) {
  runSimulation(state, worldNamed("maze"), SensorModel::lms100());
}
void BM_SimulateHospitalUtm30lx(benchmark::State& state) {
  runSimulation(state, worldNamed("hospital"), SensorModel::utm30lx());
}

BENCHMARK(BM_SimulateHospitalLms100)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SimulateMazeLms100)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SimulateHospitalUtm30lx)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
