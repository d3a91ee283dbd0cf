// Per-stage timings of the segmentation pipeline (paper II): Wall-Danielsson alone, and
// Wall-Danielsson + cascade filter, on simulated indoor scans of 541 beams (SICK LMS100:
// 270 deg at 0.5 deg) and 1081 beams (Hokuyo UTM-30LX: 270 deg at 0.25 deg).
#include <vector>

#include <benchmark/benchmark.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/ScanSegmenter.h"

namespace {
using namespace lidarseg;
using namespace lidarseg::testing;

// Scans along the office scene's corridor, so that a run averages over varied views.
std::vector<Scan> officeScans(std::size_t beams, double sigma) {
  const auto sensor = makeSensor(beams, 270, sigma, beams > 600 ? 30.0 : 20.0);
  std::vector<Scan> scans;
  for (int i = 0; i < 32; ++i) {
    const Pose2D pose{-10.0 + 0.65 * i, 1.0 + 0.3 * std::sin(0.7 * i), 0.25 * std::sin(0.3 * i)};
    scans.push_back(simulate(officeScene(), sensor, pose, 1000 + i));
  }
  return scans;
}

void BM_WallDanielsson(benchmark::State& state) {
  const auto scans = officeScans(static_cast<std::size_t>(state.range(0)), 0.012);
  const WallDanielssonSegmenter wd;
  Segmentation out;
  std::size_t i = 0, segments = 0;
  for (auto _ : state) {
    wd.segment(scans[i++ % scans.size()], out);
    segments += out.levels[0].segments.size();
    benchmark::DoNotOptimize(out.levels[0].segments.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.counters["segments_per_scan"] =
      static_cast<double>(segments) / static_cast<double>(state.iterations());
}

void BM_WallDanielssonAndCascade(benchmark::State& state) {
  const auto scans = officeScans(static_cast<std::size_t>(state.range(0)), 0.012);
  const ScanSegmenter segmenter;
  Segmentation out;
  std::size_t i = 0, segments = 0;
  for (auto _ : state) {
    segmenter.process(scans[i++ % scans.size()], out);
    segments += out.levels[3].segments.size();
    benchmark::DoNotOptimize(out.levels[3].segments.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.counters["level3_segments_per_scan"] =
      static_cast<double>(segments) / static_cast<double>(state.iterations());
}

BENCHMARK(BM_WallDanielsson)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WallDanielssonAndCascade)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
