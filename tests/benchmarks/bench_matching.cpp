// Per-scan cost of the laser odometry (paper §III.A, Table I's t): the segment matcher
// alone, segmentation + cascade + matching, and MRPT's ICP (points map + alignment) on
// the same consecutive scan pairs, so that their ratio is measured in one run.
// Scans: simulated along the office scene's corridor, 2 cm and 0.2 degrees apart
// (a robot at 1 m/s and 10 deg/s scanned at 50 Hz).
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include "SyntheticScenes.h"
#include "lidarseg/core/CorrelativeSearch.h"
#include "lidarseg/core/ScanRefiner.h"
#include "lidarseg/core/ScanSegmenter.h"
#include "lidarseg/core/SegmentMatcher.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/ScanConverter.h"
#include "lidarseg/mrpt/SegmentAlignment.h"

namespace {
using namespace lidarseg;
using namespace lidarseg::testing;

struct Pair {
  Scan previous, current;
  Pose2D motion;  // T_prev_curr
};

std::vector<Pair> officePairs(std::size_t beams) {
  const auto sensor = makeSensor(beams, 270, 0.012, beams > 600 ? 30.0 : 20.0);
  std::vector<Pair> pairs;
  for (int i = 0; i < 32; ++i) {
    const Pose2D a{-10.0 + 0.65 * i, 1.0 + 0.3 * std::sin(0.7 * i), 0.25 * std::sin(0.3 * i)};
    const Pose2D step{0.02, 0.0, 0.2 * kDeg};
    const Pose2D b = compose(a, step);
    pairs.push_back({simulate(officeScene(), sensor, a, 2000 + 2 * i), simulate(officeScene(), sensor, b, 2001 + 2 * i),
                     step});
  }
  return pairs;
}

// The previous scan of each pair, segmented (the odometry keeps them).
std::vector<Segmentation> previousSegmentations(const std::vector<Pair>& pairs) {
  const ScanSegmenter segmenter;
  std::vector<Segmentation> prev(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) segmenter.process(pairs[k].previous, prev[k]);
  return prev;
}

void BM_MatchOnly(benchmark::State& state) {
  const auto pairs = officePairs(static_cast<std::size_t>(state.range(0)));
  const ScanSegmenter segmenter;
  std::vector<Segmentation> prev(pairs.size()), cur(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    segmenter.process(pairs[k].previous, prev[k]);
    segmenter.process(pairs[k].current, cur[k]);
  }
  const SegmentMatcher matcher;
  std::size_t i = 0, matches = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % pairs.size();
    const MatchResult r = matcher.match(prev[k].levels[3].segments, cur[k].levels[3].segments, Pose2D{0.02, 0, 0});
    matches += r.matches.size();
    benchmark::DoNotOptimize(r.T_prev_curr);
  }
  state.counters["matches"] = static_cast<double>(matches) / static_cast<double>(state.iterations());
}

// What the odometry does per scan: segment the new scan (W-D + cascade) and match it with
// the previous scan's segments, which were kept.
void BM_SegmentCascadeMatch(benchmark::State& state) {
  const auto pairs = officePairs(static_cast<std::size_t>(state.range(0)));
  const ScanSegmenter segmenter;
  const std::vector<Segmentation> prev = previousSegmentations(pairs);
  const SegmentMatcher matcher;
  Segmentation current;
  std::size_t i = 0;
  double error = 0.0;
  for (auto _ : state) {
    const std::size_t k = i++ % pairs.size();
    segmenter.process(pairs[k].current, current);
    const MatchResult r = matcher.match(prev[k].levels[3].segments, current.levels[3].segments, Pose2D{0.02, 0, 0});
    error += std::hypot(r.T_prev_curr.x - pairs[k].motion.x, r.T_prev_curr.y - pairs[k].motion.y);
    benchmark::DoNotOptimize(r.T_prev_curr);
  }
  state.counters["mean_error_mm"] = 1e3 * error / static_cast<double>(state.iterations());
}

// What the odometry does per scan since issue 14: the above, then the point-to-segment
// refinement from the match (the common case: no second refinement, no search).
void BM_SegmentCascadeMatchRefine(benchmark::State& state) {
  const auto pairs = officePairs(static_cast<std::size_t>(state.range(0)));
  const ScanSegmenter segmenter;
  const std::vector<Segmentation> prev = previousSegmentations(pairs);
  const SegmentMatcher matcher;
  const ScanRefiner refiner;
  Segmentation current;
  std::size_t i = 0;
  double error = 0.0;
  for (auto _ : state) {
    const std::size_t k = i++ % pairs.size();
    segmenter.process(pairs[k].current, current);
    const MatchResult m = matcher.match(prev[k].levels[3].segments, current.levels[3].segments, Pose2D{0.02, 0, 0});
    const RefineResult r = refiner.refine(prev[k], current, m.T_prev_curr);
    error += std::hypot(r.T_key_curr.x - pairs[k].motion.x, r.T_key_curr.y - pairs[k].motion.y);
    benchmark::DoNotOptimize(r.T_key_curr);
  }
  state.counters["mean_error_mm"] = 1e3 * error / static_cast<double>(state.iterations());
}

// The recovery search (Olson's correlative matching, [search] defaults but the top-level
// block side, the second argument) from a prior 0.5 m and 0.2 rad off: the keyframe rasterised (as once per keyframe in the odometry) and
// searched. The error is the search's own (one grid cell), before any refinement.
void BM_CorrelativeSearch(benchmark::State& state) {
  const auto pairs = officePairs(static_cast<std::size_t>(state.range(0)));
  const std::vector<Segmentation> prev = previousSegmentations(pairs);
  const ScanSegmenter segmenter;
  std::vector<Segmentation> cur(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) segmenter.process(pairs[k].current, cur[k]);
  SearchParams params;
  params.coarse_cells = static_cast<std::size_t>(state.range(1));
  const CorrelativeSearch search(params);
  std::size_t i = 0;
  double error = 0.0, bounds = 0.0, evaluated = 0.0;
  for (auto _ : state) {
    const std::size_t k = i++ % pairs.size();
    const SearchResult r = search.search(prev[k].points, cur[k].points, compose(pairs[k].motion, Pose2D{0.4, -0.3, 0.2}));
    error += std::hypot(r.T_key_curr.x - pairs[k].motion.x, r.T_key_curr.y - pairs[k].motion.y);
    bounds += static_cast<double>(r.bounds);
    evaluated += static_cast<double>(r.evaluated);
    benchmark::DoNotOptimize(r.T_key_curr);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["mean_error_mm"] = 1e3 * error / n;
  state.counters["bounds"] = bounds / n;        // block bounds scored per search
  state.counters["evaluated"] = evaluated / n;  // single poses scored per search
}

// Aligns, with `aligner` (any mrpt::slam::CMetricMapsAlignmentAlgorithm), each pair's
// current scan, made a point map inside the timed loop, with the previous scan's map, from
// the same prior; the mean translation error goes in the counters.
template <typename Aligner>
void alignPointMaps(benchmark::State& state, Aligner& aligner) {
  const auto pairs = officePairs(static_cast<std::size_t>(state.range(0)));
  std::vector<mrpt::maps::CSimplePointsMap> prev(pairs.size());
  std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> cur(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto a = mrpt_adapter::makeRangeScanObservation(pairs[k].previous, "L", mrpt::poses::CPose3D(), 0.012);
    cur[k] = mrpt_adapter::makeRangeScanObservation(pairs[k].current, "L", mrpt::poses::CPose3D(), 0.012);
    prev[k].insertionOptions.minDistBetweenLaserPoints = 0.0f;
    prev[k].loadFromRangeScan(*a);
  }
  std::size_t i = 0;
  double error = 0.0;
  for (auto _ : state) {
    const std::size_t k = i++ % pairs.size();
    mrpt::maps::CSimplePointsMap current;
    current.insertionOptions.minDistBetweenLaserPoints = 0.0f;
    current.loadFromRangeScan(*cur[k]);
    const auto pdf = aligner.AlignPDF(&prev[k], &current, mrpt::poses::CPosePDFGaussian(mrpt::poses::CPose2D(0.02, 0, 0)));
    const auto m = pdf->getMeanVal();
    error += std::hypot(m.x() - pairs[k].motion.x, m.y() - pairs[k].motion.y);
    benchmark::DoNotOptimize(m);
  }
  state.counters["mean_error_mm"] = 1e3 * error / static_cast<double>(state.iterations());
}

// MRPT's ICP: build the current scan's point map, align it with the previous one from the
// same prior. Arg 1: MRPT's default parameters; arg 2: the [icp] section of
// config/default.ini, read by the loader the tools use (LidarsegConfig::loadFile), so this
// is the baseline the docs describe (every point paired; the angular threshold MRPT's
// default, decision 84: the 0.0262 set here before was never the tools' value).
void BM_MrptIcp(benchmark::State& state) {
  mrpt::slam::CICP icp;
  if (state.range(1) == 2) {
    icp.options = mrpt_adapter::LidarsegConfig::loadFile(std::string(LIDARSEG_CONFIG_DIR) + "/default.ini").icp;
  }
  alignPointMaps(state, icp);
}

// lidarseg behind MRPT's interface: SegmentAlignment::AlignPDF on the same point maps as
// BM_MrptIcp (one object for the whole run, as a caller aligning scan after scan uses it).
void BM_SegmentAlignment(benchmark::State& state) {
  mrpt_adapter::SegmentAlignment align;
  alignPointMaps(state, align);
}

}  // namespace

// Worst case (docs/performance.md, "Bounded latency"): a pathological scan pair holding
// `segments` short segments each (a picket fence of 0.3 m boards in every direction), the
// full weight matrix (band 0), matched with max_segments = 128 (the default) and with no
// bound (max_segments = segments). The bound caps the time whatever the scan holds.
void BM_MatchClutterWorstCase(benchmark::State& state) {
  const auto segments = static_cast<std::size_t>(state.range(0));
  const bool bounded = state.range(1) != 0;
  std::vector<Segment> a(segments), b(segments);
  for (std::size_t i = 0; i < segments; ++i) {
    const double bearing = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(segments);
    const double r = 3.0 + 0.5 * std::sin(7.0 * bearing);
    for (auto* s : {&a[i], &b[i]}) {
      const double shift = s == &b[i] ? 0.01 : 0.0;
      const Eigen::Vector2d c(r * std::cos(bearing) + shift, r * std::sin(bearing));
      const Eigen::Vector2d d(-std::sin(bearing), std::cos(bearing));
      s->start = c - 0.15 * d;
      s->end = c + 0.15 * d;
      s->cog = s->centroid = c;
      s->normal = Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
      s->theta_rad = bearing;
      s->rho_m = s->normal.dot(c);
      s->length_m = 0.3 + 0.001 * static_cast<double>(i % 7);
      s->num_points = 10;
      s->covariance << 1e-4, 0, 0, 1e-5;
    }
  }
  MatcherParams p;
  p.band_half_width = 0;
  p.max_segments = bounded ? 128 : segments;
  const SegmentMatcher matcher(p);
  std::size_t weights = 0;
  for (auto _ : state) {
    const MatchResult r = matcher.match(a, b, {});
    weights = r.weights_computed;
    benchmark::DoNotOptimize(r);
  }
  state.counters["weights"] = static_cast<double>(weights);
}

BENCHMARK(BM_MatchOnly)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MatchClutterWorstCase)
    ->Args({128, 1})->Args({512, 1})->Args({2048, 1})->Args({512, 0})->Args({2048, 0})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SegmentCascadeMatch)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SegmentCascadeMatchRefine)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MrptIcp)->ArgsProduct({{541, 1081}, {1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CorrelativeSearch)->ArgsProduct({{541, 1081}, {4, 8, 16, 32}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SegmentAlignment)->Arg(541)->Arg(1081)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
