#include "lidarseg/apps/PeopleApp.h"

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
#include <opencv2/videoio.hpp>

#include "ReportTools.h"
#include "lidarseg/mrpt/VisionConfig.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/vision/ImageFile.h"
#include "lidarseg/vision/PeopleDetector.h"
#include "lidarseg/vision/RegionsOfInterest.h"

namespace lidarseg::apps {

namespace fs = std::filesystem;

namespace {

// Frames of a video, a directory of images or one image.
class FrameSource {
 public:
  explicit FrameSource(const std::string& input) : input_(input) {
    if (fs::is_directory(input)) {
      for (const auto& e : fs::directory_iterator(input)) {
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
        if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".ppm" || ext == ".pgm") {
          files_.push_back(e.path().string());
        }
      }
      std::sort(files_.begin(), files_.end());
      if (files_.empty()) throw std::runtime_error("'" + input + "': no image files (png, jpg, bmp, ppm, pgm)");
    } else if (!fs::exists(input)) {
      throw std::runtime_error("'" + input + "': no such file or directory");
    } else if (vision::readImageHeader(input) || cv::haveImageReader(input)) {
      files_.push_back(input);  // read (and its size checked) by next()
    } else {
      video_.open(input);
      if (!video_.isOpened()) throw std::runtime_error("'" + input + "': neither an image nor a video OpenCV can read");
    }
  }

  // How many frames the input holds: its image files, or the frame count the video's
  // container declares (0 when it declares none); for the progress's time left only.
  std::size_t expectedFrames() const {
    if (!video_.isOpened()) return files_.size();
    const double n = video_.get(cv::CAP_PROP_FRAME_COUNT);
    return std::isfinite(n) && n > 0 ? static_cast<std::size_t>(n) : 0;
  }

  // The next frame (BGR) and its file name; false at the end.
  bool next(cv::Mat& frame, std::string& file) {
    if (video_.isOpened()) {
      file.clear();
      return video_.read(frame) && !frame.empty();
    }
    if (next_file_ >= files_.size()) return false;
    const std::string& path = files_[next_file_++];
    frame = vision::readImage(path);
    file = fs::path(path).filename().string();
    return true;
  }

 private:
  std::string input_;
  cv::VideoCapture video_;
  std::vector<std::string> files_;
  std::size_t next_file_ = 0;
};

bool centredIn(const cv::Rect& box, const std::vector<cv::Rect>& regions) {
  const cv::Point c(box.x + box.width / 2, box.y + box.height / 2);
  return std::any_of(regions.begin(), regions.end(), [&](const cv::Rect& r) { return r.contains(c); });
}

bool overlapsAny(const cv::Rect& box, const std::vector<vision::Person>& people, double iou) {
  return std::any_of(people.begin(), people.end(),
                     [&](const vision::Person& p) { return vision::intersectionOverUnion(box, p.box) >= iou; });
}

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
RegionTable readRegions(const PeopleOptions& options) {
  RegionTable regions;
  for (const std::string& r : options.rois) regions.addEveryFrame(parseRegion(r, "--roi"));
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
      : options_(options), detector_(detector), report_(report), outputs_(outputs) {
    csv_ << "frame,mode,u_min,v_min,u_max,v_max,score\n";
  }

  // Frame `index` (BGR) with its regions (pixels).
  void addFrame(std::size_t index, const cv::Mat& frame, const std::vector<cv::Rect>& rois) {
    report_.frame_size = frame.size();
    auto t0 = Clock::now();
    const vision::PeopleDetection full = detector_.detectFullFrame(frame);
    full_ms_.push_back(microsecondsSince(t0) * 1e-3);
    t0 = Clock::now();
    const vision::PeopleDetection inside = detector_.detectInRegions(frame, rois);
    rois_ms_.push_back(microsecondsSince(t0) * 1e-3);
    fraction_.push_back(inside.analysed_fraction);
    if (full_ms_.back() > 0) ratio_.push_back(rois_ms_.back() / full_ms_.back());
    ++report_.frames;
    countPeople(full.people, inside.people, rois);
    writeDetections(csv_, index, "full", full.people);
    writeDetections(csv_, index, "rois", inside.people);
    if (!options_.draw_dir.empty() && (report_.frames - 1) % options_.draw_every == 0) {
      draw(index, frame, rois, full, inside);
    }
  }

  // The per-frame samples summarised into the report.
  void summarise() {
    report_.full_ms = summarize(full_ms_);
    report_.rois_ms = summarize(rois_ms_);
    report_.analysed_fraction = summarize(fraction_);
    report_.time_ratio = summarize(ratio_);
  }

  // The detections CSV, header included.
  std::string csv() const { return csv_.str(); }

 private:
  // Whole-frame people centred in a region and found again inside the regions; detections
  // inside the regions that the whole frame also has.
  void countPeople(const std::vector<vision::Person>& full, const std::vector<vision::Person>& inside,
                   const std::vector<cv::Rect>& rois) {
    report_.people_full += full.size();
    report_.people_rois += inside.size();
    for (const vision::Person& p : full) {
      if (!centredIn(p.box, rois)) continue;
      ++report_.people_in_regions;
      if (overlapsAny(p.box, inside, options_.match_iou)) ++report_.people_still_found;
    }
    for (const vision::Person& p : inside) {
      if (overlapsAny(p.box, full, options_.match_iou)) ++report_.people_rois_confirmed;
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
  const vision::PeopleDetector& detector_;
  PeopleReport& report_;
  OutputSet& outputs_;
  std::ostringstream csv_;
  std::vector<double> full_ms_, rois_ms_, fraction_, ratio_;
};

// people.json: the report's counts and median times and shares.
Json reportJson(const PeopleReport& report) {
  return Json{{"input", report.input},
              {"frames", report.frames},
              {"full_ms_median", finiteOrNull(report.full_ms.median)},
              {"rois_ms_median", finiteOrNull(report.rois_ms.median)},
              {"analysed_fraction_median", finiteOrNull(report.analysed_fraction.median)},
              {"time_ratio_median", finiteOrNull(report.time_ratio.median)},
              {"people_full", report.people_full},
              {"people_in_regions", report.people_in_regions},
              {"people_still_found", report.people_still_found},
              {"recall_in_regions", finiteOrNull(report.recallInRegions())},
              {"people_rois", report.people_rois},
              {"people_rois_confirmed", report.people_rois_confirmed}};
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

double PeopleReport::recallInRegions() const {
  return people_in_regions == 0 ? std::nan("")
                                : static_cast<double>(people_still_found) / static_cast<double>(people_in_regions);
}

PeopleApp::PeopleApp(PeopleOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw std::invalid_argument("no input video or images given");
  if (options_.rois_path.empty() && options_.rois.empty()) {
    throw std::invalid_argument("no regions of interest: give --rois FILE.csv or --roi u_min,v_min,u_max,v_max");
  }
  if (options_.every == 0) throw std::invalid_argument("--every must be >= 1");
  if (options_.threads < 1 || options_.threads > 256) throw std::invalid_argument("-j/--jobs must be in [1, 256]");
  if (!(options_.match_iou > 0 && options_.match_iou <= 1)) throw std::invalid_argument("--match-iou must be in (0, 1]");
  if (options_.draw_every == 0) throw std::invalid_argument("--draw-every must be >= 1");
  for (const std::string& r : options_.rois) parseRegion(r, "--roi");
}

PeopleReport PeopleApp::run() {
  // Before any work: an output that is an input is refused, a second writer at once.
  OutputSet outputs;
  const PeopleOptions& o = options_;
  outputs.claimOutputs({{o.out_csv, "--out"}}, {{o.report_dir, "--report"}, {o.draw_dir, "--draw"}},
                       {o.input, o.rois_path, o.config_path});
  const vision::PeopleDetector detector(loadParams(options_.config_path));
  const RegionTable regions = readRegions(options_);
  const RestoreThreads restore{cv::getNumThreads()};
  cv::setNumThreads(options_.threads);
  FrameSource source(options_.input);
  PeopleReport report;
  report.input = options_.input;
  FramePass pass(options_, detector, report, outputs);
  if (!options_.draw_dir.empty()) fs::create_directories(options_.draw_dir);
  cv::Mat frame;
  std::string file;
  // The frames analysed: every `every`-th of the input's, at most max_frames.
  std::size_t expected = (source.expectedFrames() + options_.every - 1) / options_.every;
  if (options_.max_frames > 0 && (expected == 0 || expected > options_.max_frames)) expected = options_.max_frames;
  Progress progress("lidarseg-people", options_.progress, expected);
  for (std::size_t index = 0; source.next(frame, file); ++index) {
    if (index % options_.every != 0) continue;
    if (options_.max_frames > 0 && report.frames >= options_.max_frames) break;
    pass.addFrame(index, frame, regions.of(index, file));
    progress.update(report.frames);
  }
  progress.done(report.frames);
  if (report.frames == 0) throw std::runtime_error("'" + options_.input + "': no frame read");
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
  return os.str();
}

void PeopleApp::print(const PeopleReport& report, std::ostream& os) { os << markdown(report); }

}  // namespace lidarseg::apps
