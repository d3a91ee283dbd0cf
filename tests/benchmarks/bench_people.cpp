// HOG people detector on a real frame (opencv-doc's vtest.avi, 768 x 576): the whole frame
// against only two regions of interest (docs/performance.md). Single OpenCV thread, so the
// two costs compare.
#include <stdexcept>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/videoio.hpp>

#include "lidarseg/vision/PeopleDetector.h"

namespace {

const cv::Mat& frame() {
  static const cv::Mat f = [] {
    cv::VideoCapture cap("/usr/share/doc/opencv-doc/examples/data/vtest.avi");
    cv::Mat m;
    for (int i = 0; i <= 480; ++i) {
      if (!cap.read(m)) throw std::runtime_error("vtest.avi unreadable (package opencv-doc)");
    }
    return m;
  }();
  return f;
}

// The regions of the demo in docs/results.md: the road on the right, a stretch of path.
const std::vector<cv::Rect> kRegions = {cv::Rect(560, 60, 208, 361), cv::Rect(180, 130, 151, 171)};

void BM_HogWholeFrame(benchmark::State& state) {
  cv::setNumThreads(1);
  const lidarseg::vision::PeopleDetector det;
  std::size_t people = 0;
  for (auto _ : state) {
    const auto d = det.detectFullFrame(frame());
    people = d.people.size();
    benchmark::DoNotOptimize(people);
  }
  state.counters["people"] = static_cast<double>(people);
  state.counters["analysed"] = 1.0;
}
BENCHMARK(BM_HogWholeFrame)->Unit(benchmark::kMillisecond);

void BM_HogInsideRegions(benchmark::State& state) {
  cv::setNumThreads(1);
  const lidarseg::vision::PeopleDetector det;
  std::size_t people = 0;
  double analysed = 0;
  for (auto _ : state) {
    const auto d = det.detectInRegions(frame(), kRegions);
    people = d.people.size();
    analysed = d.analysed_fraction;
    benchmark::DoNotOptimize(people);
  }
  state.counters["people"] = static_cast<double>(people);
  state.counters["analysed"] = analysed;
}
BENCHMARK(BM_HogInsideRegions)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
