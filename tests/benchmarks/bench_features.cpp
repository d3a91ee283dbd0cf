// Time of the door and corner detector (paper §III.B) on one scan's low-level segments,
// simulated along the office scene's corridor (doors open and recessed, a side room,
// pillars, clutter): 541 beams (SICK LMS100) and 1081 beams (Hokuyo UTM-30LX). The
// segmentation is done once, outside the timed loop.
#include <vector>

#include <benchmark/benchmark.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/FeatureDetector.h"
#include "lidarseg/core/ScanSegmenter.h"

namespace {
using namespace lidarseg;
using namespace lidarseg::testing;

std::vector<Segmentation> officeSegmentations(std::size_t beams) {
  const auto sensor = makeSensor(beams, 270, 0.012, beams > 600 ? 30.0 : 20.0);
  const ScanSegmenter segmenter;
  std::vector<Segmentation> out;
  for (int i = 0; i < 32; ++i) {
    const Pose2D pose{-10.0 + 0.65 * i, 1.0 + 0.3 * std::sin(0.7 * i), 0.25 * std::sin(0.3 * i)};
    out.push_back(segmenter.process(simulate(officeScene(), sensor, pose, 1000 + i)));
  }
  return out;
}

void BM_DetectFeatures(benchmark::State& state) {
  const auto segs = officeSegmentations(static_cast<std::size_t>(state.range(0)));
  const FeatureDetector detector;
  std::vector<Feature> features;
  std::size_t i = 0, found = 0, segments = 0;
  for (auto _ : state) {
    const Segmentation& s = segs[i++ % segs.size()];
    detector.detect(s, features);
    found += features.size();
    segments += s.level(detector.params().level).segments.size();
    benchmark::DoNotOptimize(features.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  const double n = static_cast<double>(state.iterations());
  state.counters["features_per_scan"] = static_cast<double>(found) / n;
  state.counters["segments_per_scan"] = static_cast<double>(segments) / n;
}

// The whole lidar side: Wall-Danielsson + cascade + detection.
void BM_SegmentAndDetect(benchmark::State& state) {
  const auto sensor = makeSensor(static_cast<std::size_t>(state.range(0)), 270, 0.012, 20.0);
  std::vector<Scan> scans;
  for (int i = 0; i < 32; ++i) {
    const Pose2D pose{-10.0 + 0.65 * i, 1.0 + 0.3 * std::sin(0.7 * i), 0.25 * std::sin(0.3 * i)};
    scans.push_back(simulate(officeScene(), sensor, pose, 1000 + i));
  }
  const ScanSegmenter segmenter;
  const FeatureDetector detector;
  Segmentation seg;
  std::vector<Feature> features;
  std::size_t i = 0;
  for (auto _ : state) {
    segmenter.process(scans[i++ % scans.size()], seg);
    detector.detect(seg, features);
    benchmark::DoNotOptimize(features.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}

BENCHMARK(BM_DetectFeatures)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SegmentAndDetect)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);

}  // namespace
BENCHMARK_MAIN();
