#include "lidarseg/apps/PeopleApp.h"

#include "lidarseg/apps/CommandLine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ReportTools.h"
#include "lidarseg/mrpt/VisionConfig.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/vision/FrameSource.h"
#include "lidarseg/vision/ImageFile.h"
#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/vision/RegionTable.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::apps {

namespace fs = std::filesystem;

namespace {

void writeDetections(std::ostream& os, std::size_t frame, const char* mode, const std::vector<vision::Person>& people) {
  for (const vision::Person& p : people) {
    os << frame << ',' << mode << ',' << p.box.x << ',' << p.box.y << ',' << p.box.x + p.box.width - 1 << ','
       << p.box.y + p.box.height - 1 << ',' << std::setprecision(4) << p.score << '\n';
  }
}

// The [people] section of the configuration; the defaults without a file.
vision::PeopleDetectorParams loadParams(const std::string& config_path) {
  if (config_path.empty()) return {};
  return mrpt_adapter::LidarsegConfig::loadFile(config_path).vision.people;
}

// The regions given on the command line (every frame) and in the regions file.
vision::RegionTable readRegions(const PeopleOptions& options) {
  vision::RegionTable regions;
  for (const std::string& r : options.rois) regions.addEveryFrame(vision::parseRegion(r, "--roi"));
  if (!options.rois_path.empty()) regions.read(options.rois_path);
  return regions;
}

// Puts OpenCV's worker threads back to `n` at the end of the run.
struct RestoreThreads {
  int n;
  ~RestoreThreads() { cv::setNumThreads(n); }
};

// The detector on each analysed frame, once on the whole frame and once inside the regions:
// times, people counted and matched, CSV rows and, every draw_every frame, a picture.
class FramePass {
 public:
  // Writes the CSV header.
  FramePass(const PeopleOptions& options, const vision::PeopleDetector& detector, PeopleReport& report,
            OutputSet& outputs)
      : options_(options), comparison_(detector, options.match_iou, report), report_(report), outputs_(outputs) {
    csv_ << "frame,mode,u_min,v_min,u_max,v_max,score\n";
  }

  // Frame `index` (BGR) with its regions (pixels).
  void addFrame(std::size_t index, const cv::Mat& frame, const std::vector<cv::Rect>& rois) {
    countRegionsOutside(index, frame, rois);
    if (!rois.empty()) ++report_.frames_with_regions;
    const auto d = comparison_.add(frame, rois);
    writeDetections(csv_, index, "full", d.full.people);
    writeDetections(csv_, index, "rois", d.inside.people);
    if (!options_.draw_dir.empty() && (report_.frames - 1) % options_.draw_every == 0) {
      draw(index, frame, rois, d.full, d.inside);
    }
  }

  // The per-frame samples summarised into the report.
  void summarise() const { comparison_.summarise(); }

  // The detections CSV, header included.
  std::string csv() const { return csv_.str(); }

 private:
  // Regions with no pixel in the frame: counted, the first named (inclusive corners, as
  // given), for the run's warning.
  void countRegionsOutside(std::size_t index, const cv::Mat& frame, const std::vector<cv::Rect>& rois) {
    const cv::Rect whole(0, 0, frame.cols, frame.rows);
    for (const cv::Rect& r : rois) {
      if ((r & whole).area() > 0) continue;
      if (report_.regions_outside++ == 0) {
        report_.first_region_outside = "frame " + std::to_string(index) + ": region " + std::to_string(r.x) + "," +
                                       std::to_string(r.y) + "," + std::to_string(r.x + r.width - 1) + "," +
                                       std::to_string(r.y + r.height - 1) + " outside the " + std::to_string(frame.cols) +
                                       " x " + std::to_string(frame.rows) + " frame";
      }
    }
  }

  // The frame with the analysed crops (grey), regions (yellow), whole-frame detections (blue)
  // and detections inside the regions (red), as people_NNNNNN.png.
  void draw(std::size_t index, const cv::Mat& frame, const std::vector<cv::Rect>& rois,
            const vision::PeopleDetection& full, const vision::PeopleDetection& inside) {
    cv::Mat pic = frame.clone();
    for (const cv::Rect& a : inside.analysed) cv::rectangle(pic, a, cv::Scalar(160, 160, 160), 1);
    for (const cv::Rect& r : rois) cv::rectangle(pic, r, cv::Scalar(0, 220, 255), 2);
    for (const vision::Person& p : full.people) cv::rectangle(pic, p.box, cv::Scalar(255, 120, 0), 3);
    for (const vision::Person& p : inside.people) cv::rectangle(pic, p.box, cv::Scalar(0, 0, 230), 1);
    char name[32];
    std::snprintf(name, sizeof(name), "people_%06zu.png", index);
    outputs_.add(options_.draw_dir + "/" + name, encodePng(pic));
  }

  const PeopleOptions& options_;
  vision::PeopleComparison comparison_;
  PeopleReport& report_;
  OutputSet& outputs_;
  std::ostringstream csv_;
};

// people.json: the report's counts and median times and shares.
Json reportJson(const PeopleReport& report) {
  return Json{{"input", report.input},
              {"frames", report.frames},
              {"frames_skipped", report.frames_skipped},
              {"warnings", report.warnings},
              {"full_ms_median", finiteOrNull(report.full_ms.median)},
              {"rois_ms_median", finiteOrNull(report.rois_ms.median)},
              {"analysed_fraction_median", finiteOrNull(report.analysed_fraction.median)},
              {"time_ratio_median", finiteOrNull(report.time_ratio.median)},
              {"people_full", report.people_full},
              {"people_in_regions", report.people_in_regions},
              {"people_still_found", report.people_still_found},
              {"recall_in_regions", finiteOrNull(report.recallInRegions())},
              {"people_rois", report.people_rois},
              {"people_rois_confirmed", report.people_rois_confirmed},
              {"regions_outside", report.regions_outside},
              {"frames_with_regions", report.frames_with_regions}};
}

// The detections CSV and the report put in place, together with the frames drawn.
void writeOutputs(const PeopleOptions& options, const PeopleReport& report, const FramePass& pass,
                  OutputSet& outputs) {
  if (!options.out_csv.empty()) outputs.add(options.out_csv, pass.csv());
  if (!options.report_dir.empty()) {
    fs::create_directories(options.report_dir);
    outputs.add(options.report_dir + "/people.md", PeopleApp::markdown(report));
    outputs.add(options.report_dir + "/people.json", jsonText(reportJson(report)));
  }
  outputs.commit();
}

}  // namespace

PeopleApp::PeopleApp(PeopleOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw UsageError("no input video or images given");
  if (options_.rois_path.empty() && options_.rois.empty()) {
    throw UsageError("no regions of interest: give --rois FILE.csv or --roi u_min,v_min,u_max,v_max");
  }
  if (options_.every == 0) throw UsageError("--every must be >= 1");
  if (options_.threads < 1 || options_.threads > 256) throw UsageError("-j/--jobs must be in [1, 256]");
  if (!(options_.match_iou > 0 && options_.match_iou <= 1)) throw UsageError("--match-iou must be in (0, 1]");
  if (options_.draw_every == 0) throw UsageError("--draw-every must be >= 1");
  for (const std::string& r : options_.rois) checkedOption("--roi", [&] { (void)vision::parseRegion(r, "--roi"); });
}

namespace {

// Before any work: an output that is an input is refused, a second writer at once.
void claimOutputs(const PeopleOptions& o, OutputSet& outputs) {
  outputs.claimOutputs({{o.out_csv, "--out"}},
                       {{o.report_dir, "--report", {"people.md", "people.json"}}, {o.draw_dir, "--draw", {}, {{"people_", ".png"}}}},
                       {o.input, o.rois_path, o.config_path});
  if (!o.draw_dir.empty()) fs::create_directories(o.draw_dir);
}

// Every `every`-th frame of the input (up to max_frames) through the pass with its
// regions, with progress on stderr.
void readFrames(const PeopleOptions& o, const vision::RegionTable& regions, FramePass& pass, PeopleReport& report) {
  vision::FrameSource source(o.input);
  cv::Mat frame;
  std::string file;
  // The frames analysed: every `every`-th of the input's, at most max_frames.
  std::size_t expected = (source.expectedFrames() + o.every - 1) / o.every;
  if (o.max_frames > 0 && (expected == 0 || expected > o.max_frames)) expected = o.max_frames;
  Progress progress("lidarseg-people", o.progress, expected);
  while (source.next(frame, file)) {
    // The frame's own number: a frame skipped as undecodable does not shift the regions.
    const std::size_t index = source.frameIndex();
    if (index % o.every != 0) continue;
    if (o.max_frames > 0 && report.frames >= o.max_frames) break;
    try {
      pass.addFrame(index, frame, regions.of(index, file));
    } catch (const std::invalid_argument& e) {  // a frame the detector refuses: name it
      throw std::invalid_argument((file.empty() ? o.input + " frame " + std::to_string(index) : file) + ": " +
                                  e.what());
    }
    progress.update(report.frames);
  }
  progress.done(report.frames);
  report.frames_skipped = source.skippedFrameCount();
  report.warnings = source.skippedFrames();
  if (report.frames == 0) {
    throw std::runtime_error("'" + o.input + "': no frame read" +
                             (report.warnings.empty() ? std::string() : " (" + report.warnings.front() + ")"));
  }
}

}  // namespace

PeopleReport PeopleApp::run() {
  OutputSet outputs;
  claimOutputs(options_, outputs);
  const vision::PeopleDetector detector(loadParams(options_.config_path));
  const vision::RegionTable regions = readRegions(options_);
  const RestoreThreads restore{cv::getNumThreads()};
  cv::setNumThreads(options_.threads);
  PeopleReport report;
  report.input = options_.input;
  FramePass pass(options_, detector, report, outputs);
  readFrames(options_, regions, pass, report);
  pass.summarise();
  writeOutputs(options_, report, pass, outputs);
  return report;
}

std::string PeopleApp::markdown(const PeopleReport& r) {
  std::ostringstream os;
  os << "# People inside the regions of interest: " << r.input << "\n\n";
  os << r.frames << " frames of " << r.frame_size.width << " x " << r.frame_size.height
     << " pixels, OpenCV's HOG people detector (default coefficients).\n\n";
  os << "| | whole frame | inside the regions |\n|---|---:|---:|\n";
  os << "| time per frame, median (ms) | " << fixed(r.full_ms.median, 2) << " | " << fixed(r.rois_ms.median, 2) << " |\n";
  os << "| time per frame, p99 (ms) | " << fixed(r.full_ms.p99, 2) << " | " << fixed(r.rois_ms.p99, 2) << " |\n";
  os << "| share of the image analysed, median | 1.000 | " << fixed(r.analysed_fraction.median, 3) << " |\n";
  os << "| people detected | " << r.people_full << " | " << r.people_rois << " |\n\n";
  os << "Time inside the regions over time on the whole frame, per frame: median " << fixed(r.time_ratio.median, 3)
     << " (share of the image analysed: median " << fixed(r.analysed_fraction.median, 3) << ").\n\n";
  os << "People found on the whole frame and centred inside a region: " << r.people_in_regions
     << "; still found by the detection inside the regions: " << r.people_still_found << " (recall "
     << fixed(r.recallInRegions(), 3) << "). Detections inside the regions that the whole frame also has: "
     << r.people_rois_confirmed << " of " << r.people_rois << ".\n";
  if (r.frames_with_regions == 0) {
    os << "\nNo frame analysed has a region of interest: the regions name no frame or image of this input.\n";
  }
  if (r.regions_outside > 0) {
    os << "\nRegions wholly outside their frame (not analysed): " << r.regions_outside << ", the first: "
       << r.first_region_outside << ".\n";
  }
  if (r.frames_skipped > 0) {
    os << "\nFrames skipped (could not be decoded): " << r.frames_skipped << ", the first: "
       << (r.warnings.empty() ? std::string("?") : r.warnings.front()) << ".\n";
  }
  return os.str();
}

void PeopleApp::print(const PeopleReport& report, std::ostream& os) { os << markdown(report); }

void PeopleApp::printWarnings(const PeopleReport& report, std::ostream& err) {
  if (report.frames > 0 && report.frames_with_regions == 0) {
    err << "lidarseg-people: warning: no frame of the " << report.frames
        << " analysed has a region of interest (the regions name no frame or image of this input)\n";
  }
  if (report.regions_outside > 0) {
    err << "lidarseg-people: warning: " << report.regions_outside
        << " regions lie wholly outside their frame and were not analysed, the first: " << report.first_region_outside
        << "\n";
  }
  if (report.frames_skipped == 0) return;
  err << "lidarseg-people: warning: " << report.frames_skipped << " frames skipped, the first: "
      << (report.warnings.empty() ? std::string("?") : report.warnings.front()) << "\n";
}

}  // namespace lidarseg::apps
