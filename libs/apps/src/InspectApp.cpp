#include "lidarseg/apps/InspectApp.h"

#include "lidarseg/apps/CommandLine.h"
#include "lidarseg/core/NumberText.h"
#include "lidarseg/vision/ImageFile.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/img/CImage.h>
#include <opencv2/imgcodecs.hpp>

#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/RunEvaluation.h"
#include "lidarseg/inspect/Drawing.h"
#include "lidarseg/inspect/LayerSwitches.h"
#include "lidarseg/inspect/LogReport.h"
#include "lidarseg/eval/StampedTrajectory.h"

namespace lidarseg::apps {

using vision::encodePng;

using report::writeFileAtomically;
using report::refuseOverwritingInput;
using report::OutputSet;

namespace fs = std::filesystem;
using inspect::Layers;
using inspect::Session;

namespace {

bool endsWith(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

}  // namespace

InspectApp::InspectApp(InspectOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw UsageError("no input log given");
  if (options_.width < 200 || options_.height < 200 || options_.width > 8192 || options_.height > 8192) {
    throw UsageError("--width/--height: from 200 to 8192 pixels (got " + std::to_string(options_.width) + " x " +
                                std::to_string(options_.height) + ")");
  }
  if (!options_.render_out.empty() && !endsWith(options_.render_out, ".png") && !endsWith(options_.render_out, ".svg")) {
    throw UsageError("--draw '" + options_.render_out + "': the name must end in .png or .svg");
  }
  if (!options_.screenshot_out.empty() && !endsWith(options_.screenshot_out, ".png")) {
    throw UsageError("--screenshot '" + options_.screenshot_out + "': the name must end in .png");
  }
  checkedOption("--layers", [&] { (void)inspect::parseLayers(options_.layers); });
  for (const std::string& r : options_.references) {
    if (r.find('=') == std::string::npos || r.front() == '=' || r.back() == '=') {
      throw UsageError("--trajectory '" + r + "': expected NAME=FILE.tum");
    }
  }
}

std::vector<std::string> InspectApp::keyHelp() {
  return {"n / Right: next scan    b / Left: previous    Shift: 10 scans    Home / End: first / last",
          "digits then g: go to scan    digits then t: go to time (s from the first scan)    Space: play / pause",
          "layers: r raw  z x c v levels 0-3  i indices  k predicted keyframe  m matches  f doors/corners",
          "        o trajectories  a camera    u / d: zoom in / out",
          "tuning: [ ] W-D threshold  ; ' fusion line distance  , . erosion length  - = matcher COG gate",
          "s: save parameters (INI)    h: this help    q / Esc: quit"};
}

std::unique_ptr<Session> InspectApp::open() {
  inspect::InspectorParams params;
  if (!options_.config_path.empty()) params = inspect::InspectorParams::fromFile(options_.config_path);
  auto session = std::make_unique<Session>(options_.input, options_.sensor_label, params);
  // Found as lidarseg-odometry finds it: beside a rawlog or a CARMEN log.
  truth_path_ = options_.truth_path.empty() ? report::groundTruthBeside(options_.input) : options_.truth_path;
  if (!truth_path_.empty()) {
    eval::StampedTrajectory truth = eval::readTum(truth_path_);
    // An empty file draws nothing and pairs with no scan: said once, whatever is asked.
    if (truth.empty()) std::cerr << "lidarseg-inspect: warning: ground truth '" << truth_path_ << "' holds no pose\n";
    session->addReference({"ground truth", std::move(truth)});
  }
  for (const std::string& r : options_.references) {
    const auto eq = r.find('=');
    eval::StampedTrajectory reference = eval::readTum(r.substr(eq + 1));
    if (reference.empty()) {
      std::cerr << "lidarseg-inspect: warning: trajectory '" << r.substr(0, eq) << "' ('" << r.substr(eq + 1)
                << "') holds no pose\n";
    }
    session->addReference({r.substr(0, eq), std::move(reference)});
  }
  return session;
}

namespace {

// Before any work: an output that is an input is refused, a second writer at once. The
// report's own output set shares this lock. A picture is one file written atomically; the
// report is a set of files.
void claimOutputs(const InspectOptions& o, OutputSet& claimed) {
  std::vector<std::string> inputs = {o.input, o.config_path, o.truth_path};
  for (const std::string& r : o.references) inputs.push_back(r.substr(r.find('=') + 1));
  // The pictures are claimed too (their folders locked), and checked with the report's files
  // against the inputs and each other.
  claimed.claimOutputs({{o.render_out, "--draw"}, {o.screenshot_out, "--screenshot"}},
                       {{o.report_dir, "-o", inspect::reportFileNames(), {{"frames/scan_", ".png"}}}}, inputs);
}

}  // namespace

namespace {
// How far past the last scan's time --time may ask and still mean the last scan (s).
constexpr double kTimePastTheEndS = 1.0;
}  // namespace

std::size_t InspectApp::scanAtTime(inspect::Session& session, double t_s) {
  if (!std::isfinite(t_s) || t_s < 0.0) {
    throw std::runtime_error("--time " + numberText(t_s) + " s: times count from the log's first scan (>= 0)");
  }
  const double first = session.frame(0).stamp_s;
  const std::size_t k = session.indexAtTime(first + t_s);
  const double at = session.frame(k).stamp_s - first;
  if (t_s > at + kTimePastTheEndS) {
    throw std::runtime_error("--time " + numberText(t_s) + " s: past the end of '" + options_.input +
                             "', whose last scan is at " + numberText(std::round(at * 1e3) / 1e3) + " s from its first");
  }
  return k;
}

int InspectApp::run() {
  // Held in an optional: the window leaves the process without unwinding (see
  // InspectorWindow::leave) and releases it first.
  std::optional<OutputSet> claimed(std::in_place);
  claimOutputs(options_, *claimed);
  auto session = open();
  if (options_.time_s) options_.frame = scanAtTime(*session, *options_.time_s);
  if (!options_.report_dir.empty()) {
    const InspectReport r = writeReport(*session);
    std::cout << "report: " << options_.report_dir << "/index.html (" << r.scans << " scans, " << r.gallery.size()
              << " frames in the gallery)\n";
    if (options_.render_out.empty() && options_.screenshot_out.empty()) return 0;
  }
  if (!options_.render_out.empty()) {
    render(*session);
    if (options_.screenshot_out.empty()) return 0;
  }
  return window(*session, [&claimed] { claimed.reset(); });
}

void InspectApp::render(Session& session) {
  const inspect::Drawing d = session.draw(options_.frame, inspect::parseLayers(options_.layers));
  const cv::Size size(options_.width, options_.height);
  writeFileAtomically(options_.render_out, endsWith(options_.render_out, ".svg") ? inspect::renderSvg(d, size)
                                                                                 : encodePng(inspect::renderPng(d, size)));
  std::cout << "scan " << options_.frame << " drawn to " << options_.render_out << "\n";
}

namespace {

// The interactive window on one session: the scan it shows and the keys of keyHelp().
class InspectorWindow {
 public:
  // Opens the window at options.frame; `release` gives up the run's claims on its outputs
  // (called before the process leaves).
  InspectorWindow(Session& session, const InspectOptions& options, std::function<void()> release);
  // Shows the scan, writes what the window shows to options.screenshot_out, leaves.
  [[noreturn]] void screenshot();
  // Follows the keys until q, Esc or the window is closed, then leaves.
  [[noreturn]] void loop();

 private:
  // Draws the scan with the zoom, the number being typed, the message and the keys.
  void show();
  // One capture of the window; false if there is none yet or it is all black.
  bool grab(mrpt::img::CImage& grabbed);
  // Reads one key and acts on it; true for a digit of a number being typed.
  bool onKey();
  // r z x c v i k m f o a: shows or hides a layer; false for any other key.
  bool toggleLayer(int k);
  // n b Left Right Home End g t: goes to another scan; false for any other key.
  bool navigate(int k, long long step);
  // [ ] ; ' , . - =: a parameter times 1/1.1 or 1.1; false for any other key.
  bool tuneKey(int k);
  // Space u d h s q Esc: play, zoom, help, save, quit.
  void command(int k);
  // Goes to scan `target`, clamped to the log; an unreadable scan stops playing and says why.
  void go(long long target);
  // Changes the parameters (the scan is processed again) and says `what`, or why not.
  void tune(const std::function<void(inspect::InspectorParams&)>& change, const std::string& what);
  // Writes the parameters as INI to options.save_path.
  void saveParams();
  // MRPT's window lives on a GUI thread that can still be drawing when the window object is
  // destroyed at exit (a rare crash in its teardown under Xvfb). Everything the inspector
  // writes is on disk by then: the claims are released (a folder created for an output and
  // left empty is removed) and the process leaves without the window's teardown.
  [[noreturn]] void leave(int code);

  Session& session_;
  const InspectOptions& options_;
  Layers layers_;
  mrpt::gui::CDisplayWindow3D win_;
  std::size_t index_;
  double zoom_ = 1.0;
  bool playing_ = false, help_ = false, dirty_ = true;
  std::string number_, message_;
  cv::Mat shown_;
  std::function<void()> release_;
};

InspectorWindow::InspectorWindow(Session& session, const InspectOptions& options, std::function<void()> release)
    : session_(session),
      options_(options),
      layers_(inspect::parseLayers(options.layers)),
      win_("lidarseg-inspect: " + fs::path(options.input).filename().string(), static_cast<unsigned>(options.width),
           static_cast<unsigned>(options.height)),
      index_(options.frame),
      release_(std::move(release)) {
  // A display that cannot be reached (a stale DISPLAY, a closed X server): MRPT's GUI thread
  // gives up without a window, and the loop would end at once as if the user had closed it.
  // A slow display (Xvfb on a loaded machine) gets its time: the wait ends when the context
  // is ready or the window is gone, at most kWaitForDisplayS.
  constexpr double kWaitForDisplayS = 60.0;
  const auto start = std::chrono::steady_clock::now();
  bool ready = false;
  while (!(ready = win_.wait_for_GL_context(0.5)) && win_.isOpen() &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < kWaitForDisplayS) {
  }
  if (!ready || !win_.isOpen()) {
    const char* display = std::getenv("DISPLAY");
    std::cerr << "lidarseg-inspect: error: cannot open a window on display '" << (display != nullptr ? display : "")
              << "': use --render FRAME --out FILE.png or --report DIR, or run under xvfb-run\n";
    leave(1);
  }
}

void InspectorWindow::leave(int code) {
  if (release_) release_();
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
}

void InspectorWindow::screenshot() {
  show();
  // Give the window time to draw, then capture what it shows.
  win_.captureImagesStart();
  mrpt::img::CImage grabbed;
  bool got = false;
  for (int i = 0; i < 50 && !got; ++i) got = grab(grabbed);
  // Stop grabbing and let the GUI thread finish its frame before the window goes away.
  win_.captureImagesStop();
  win_.forceRepaint();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  if (got) {
    writeFileAtomically(options_.screenshot_out, encodePng(grabbed.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY)));
    std::cout << "screenshot of the window (scan " << index_ << ") written to " << options_.screenshot_out << "\n";
    leave(0);
  }
  std::cerr << "lidarseg-inspect: the GL driver gave no window image; writing the picture the window shows\n";
  writeFileAtomically(options_.screenshot_out, encodePng(shown_));
  leave(0);
}

bool InspectorWindow::grab(mrpt::img::CImage& grabbed) {
  win_.forceRepaint();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!win_.getLastWindowImage(grabbed) || grabbed.getWidth() == 0) return false;
  cv::Scalar mean, sd;
  cv::meanStdDev(grabbed.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY), mean, sd);
  return sd[0] + sd[1] + sd[2] > 1.0;  // an all-black grab (some GL drivers) is no screenshot
}

void InspectorWindow::loop() {
  auto last_play = std::chrono::steady_clock::now();
  while (win_.isOpen()) {
    if (dirty_) show();
    if (win_.keyHit() && onKey()) continue;  // a digit: show it at once
    if (playing_ && std::chrono::steady_clock::now() - last_play > std::chrono::milliseconds(100)) {
      last_play = std::chrono::steady_clock::now();
      go(static_cast<long long>(index_) + 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(15));
  }
  leave(0);
}

void InspectorWindow::show() {
  inspect::Drawing d = session_.draw(index_, layers_);
  d.view_half_width_m *= zoom_;
  if (!number_.empty()) d.status.push_back("> " + number_);
  if (!message_.empty()) d.status.push_back(message_);
  if (help_) {
    for (const std::string& k : InspectApp::keyHelp()) d.status.push_back(k);
  } else {
    d.status.push_back("h: keys");
  }
  shown_ = inspect::renderPng(d, cv::Size(options_.width, options_.height));
  win_.setImageView(mrpt::img::CImage(shown_, mrpt::img::DEEP_COPY));
  win_.forceRepaint();
  dirty_ = false;
  if (options_.trace) std::cout << "shown scan " << index_ << (message_.empty() ? "" : " (" + message_ + ")") << std::endl;
}

bool InspectorWindow::onKey() {
  mrpt::gui::mrptKeyModifier mod = mrpt::gui::MRPTKMOD_NONE;
  const int key = win_.getPushedKey(&mod);
  const long long step = (mod & mrpt::gui::MRPTKMOD_SHIFT) != 0 ? 10 : 1;
  message_.clear();
  if (key >= '0' && key <= '9' && number_.size() < 12) {
    number_ += static_cast<char>(key);
    dirty_ = true;
    return true;
  }
  const int k = (key < 256) ? std::toupper(key) : key;
  if (!toggleLayer(k) && !navigate(k, step) && !tuneKey(k)) command(k);
  return false;
}

bool InspectorWindow::toggleLayer(int k) {
  if (!inspect::toggleLayer(layers_, k)) return false;
  dirty_ = true;
  return true;
}

bool InspectorWindow::navigate(int k, long long step) {
  const auto here = static_cast<long long>(index_);
  switch (k) {
    case 'N': case mrpt::gui::MRPTK_RIGHT: go(here + step); return true;
    case 'B': case mrpt::gui::MRPTK_LEFT: go(here - step); return true;
    case mrpt::gui::MRPTK_HOME: go(0); return true;
    case mrpt::gui::MRPTK_END: go(static_cast<long long>(session_.countAll()) - 1); return true;
    case 'G': if (!number_.empty()) go(std::stoll(number_)); number_.clear(); return true;
    case 'T':
      if (!number_.empty()) go(static_cast<long long>(session_.indexAtTime(session_.frame(0).stamp_s + std::stod(number_))));
      number_.clear();
      return true;
    default: return false;
  }
}

bool InspectorWindow::tuneKey(int k) {
  const auto factor = [k](int up) { return k == up ? 1.1 : 1 / 1.1; };
  const auto times = [k](int up) { return std::string(k == up ? "x1.1" : "x1/1.1"); };
  switch (k) {
    case '[': case ']': {
      const double f = factor(']');
      const double wd_m = session_.params().odometry.segmentation.wall_danielsson.threshold_m * f;
      char status[48];
      std::snprintf(status, sizeof status, "W-D threshold %.4g m", wd_m);
      tune([f](auto& p) { p.odometry.segmentation.wall_danielsson.threshold_m *= f; }, status);
      return true;
    }
    case ';': case '\'':
      tune([f = factor('\'')](auto& p) {
        p.odometry.segmentation.cascade.first_fusion.max_line_distance_m *= f;
        p.odometry.segmentation.cascade.second_fusion.max_line_distance_m *= f;
      }, "fusion line distance " + times('\''));
      return true;
    case ',': case '.':
      tune([f = factor('.')](auto& p) { p.odometry.segmentation.cascade.erosion.min_length_m *= f; },
           "erosion length " + times('.'));
      return true;
    case '-': case '=':
      tune([f = factor('=')](auto& p) { p.odometry.matcher.cog_gate_m *= f; }, "matcher COG gate " + times('='));
      return true;
    default: return false;
  }
}

void InspectorWindow::command(int k) {
  switch (k) {
    case ' ': playing_ = !playing_; break;
    case 'U': zoom_ = std::max(0.1, zoom_ / 1.25); break;
    case 'D': zoom_ = std::min(10.0, zoom_ * 1.25); break;
    case 'H': help_ = !help_; break;
    case 'S': saveParams(); break;
    case 'Q': case mrpt::gui::MRPTK_ESCAPE:
      std::cout << "quit at scan " << index_ << "\n";
      leave(0);
    default: return;
  }
  dirty_ = true;
}

void InspectorWindow::go(long long target) {
  if (target < 0) target = 0;
  try {
    session_.frame(static_cast<std::size_t>(target));
    index_ = static_cast<std::size_t>(target);
  } catch (const std::out_of_range&) {
    index_ = session_.scansRead() - 1;
    playing_ = false;
  } catch (const std::exception& e) {  // an unreadable part of the log: say so, stay
    message_ = e.what();
    playing_ = false;
  }
  dirty_ = true;
}

void InspectorWindow::tune(const std::function<void(inspect::InspectorParams&)>& change, const std::string& what) {
  inspect::InspectorParams p = session_.params();
  change(p);
  try {
    session_.setParams(p);
    message_ = what;
  } catch (const std::invalid_argument& e) {
    message_ = std::string("rejected: ") + e.what();
  }
  dirty_ = true;
}

void InspectorWindow::saveParams() {
  try {
    session_.params().saveIni(options_.save_path);
    message_ = "parameters saved to " + options_.save_path;
  } catch (const std::exception& e) {
    message_ = std::string("not saved: ") + e.what();
  }
}

}  // namespace

int InspectApp::window(Session& session, const std::function<void()>& release) {
  if (std::getenv("DISPLAY") == nullptr) {
    throw std::runtime_error("no display (DISPLAY unset): use --render FRAME --out FILE.png, or run under xvfb-run");
  }
  InspectorWindow win(session, options_, release);
  if (!options_.screenshot_out.empty()) win.screenshot();
  win.loop();
}

InspectReport InspectApp::writeReport(inspect::Session& session) {
  const InspectReport r = inspect::writeLogReport(
      session, {options_.report_dir, options_.input, options_.layers, options_.gallery, options_.progress, truth_path_});
  if (!r.truth_problem.empty()) std::cerr << "lidarseg-inspect: warning: " << r.truth_problem << "\n";
  if (!r.no_plots.empty()) std::cerr << "lidarseg-inspect: warning: no plots in the report: " << r.no_plots << "\n";
  return r;
}

}  // namespace lidarseg::apps
