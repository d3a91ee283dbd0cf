#include "lidarseg/apps/InspectApp.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/img/CImage.h>
#include <opencv2/imgcodecs.hpp>

#include "Png.h"
#include "OutputFiles.h"
#include "lidarseg/apps/inspect/Drawing.h"
#include "lidarseg/eval/StampedTrajectory.h"
#include "lidarseg/eval/Csv.h"

namespace lidarseg::apps {

namespace fs = std::filesystem;
using inspect::Layers;
using inspect::Session;

namespace {

bool endsWith(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

}  // namespace

InspectApp::InspectApp(InspectOptions options) : options_(std::move(options)) {
  if (options_.input.empty()) throw std::invalid_argument("no input log given");
  if (options_.width < 200 || options_.height < 200) throw std::invalid_argument("--size: at least 200 x 200 pixels");
  if (!options_.render_out.empty() && !endsWith(options_.render_out, ".png") && !endsWith(options_.render_out, ".svg")) {
    throw std::invalid_argument("--out '" + options_.render_out + "': the name must end in .png or .svg");
  }
  if (!options_.screenshot_out.empty() && !endsWith(options_.screenshot_out, ".png")) {
    throw std::invalid_argument("--screenshot '" + options_.screenshot_out + "': the name must end in .png");
  }
  parseLayers(options_.layers);
  for (const std::string& r : options_.references) {
    if (r.find('=') == std::string::npos || r.front() == '=' || r.back() == '=') {
      throw std::invalid_argument("--trajectory '" + r + "': expected NAME=FILE.tum");
    }
  }
}

Layers InspectApp::parseLayers(const std::string& list) {
  Layers l;
  if (list.empty()) return l;
  l = Layers{};
  l.raw_points = l.indices = l.predicted = l.matches = l.features = l.trajectory = l.camera = false;
  l.levels = {false, false, false, false};
  for (const std::string& name : eval::splitCsvLine(list)) {
    if (name == "raw") l.raw_points = true;
    else if (name.size() == 2 && name[0] == 'l' && name[1] >= '0' && name[1] <= '3') l.levels[name[1] - '0'] = true;
    else if (name == "indices") l.indices = true;
    else if (name == "predicted") l.predicted = true;
    else if (name == "matches") l.matches = true;
    else if (name == "features") l.features = true;
    else if (name == "trajectory") l.trajectory = true;
    else if (name == "camera") l.camera = true;
    else if (name == "all") {
      l.raw_points = l.indices = l.predicted = l.matches = l.features = l.trajectory = l.camera = true;
      l.levels = {true, true, true, true};
    } else {
      throw std::invalid_argument("--layers: unknown layer '" + name +
                                  "' (raw, l0, l1, l2, l3, indices, predicted, matches, features, trajectory, camera, all)");
    }
  }
  return l;
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
  std::string truth = options_.truth_path;
  if (truth.empty()) {
    std::string stem = options_.input;
    if (endsWith(stem, ".rawlog")) stem.resize(stem.size() - 7);
    if (fs::exists(stem + ".gt.tum")) truth = stem + ".gt.tum";
  }
  if (!truth.empty()) session->addReference({"ground truth", eval::readTum(truth)});
  for (const std::string& r : options_.references) {
    const auto eq = r.find('=');
    session->addReference({r.substr(0, eq), eval::readTum(r.substr(eq + 1))});
  }
  return session;
}

int InspectApp::run() {
  auto session = open();
  std::size_t frame = options_.frame;
  if (options_.time_s) frame = session->indexAtTime(session->frame(0).stamp_s + *options_.time_s);
  if (!options_.report_dir.empty()) {
    const InspectReport r = writeReport(*session);
    std::cout << "report: " << options_.report_dir << "/index.html (" << r.scans << " scans, " << r.gallery.size()
              << " frames in the gallery)\n";
    if (options_.render_out.empty() && options_.screenshot_out.empty()) return 0;
  }
  if (!options_.render_out.empty()) {
    const inspect::Drawing d = session->draw(frame, parseLayers(options_.layers));
    const cv::Size size(options_.width, options_.height);
    writeFileAtomically(options_.render_out, endsWith(options_.render_out, ".svg") ? inspect::renderSvg(d, size)
                                                                                   : encodePng(inspect::renderPng(d, size)));
    std::cout << "scan " << frame << " drawn to " << options_.render_out << "\n";
    if (options_.screenshot_out.empty()) return 0;
  }
  options_.frame = frame;
  return window(*session);
}

namespace {
// MRPT's window lives on a GUI thread that can still be drawing when the window object is
// destroyed at exit (a rare crash in its teardown under Xvfb). Everything the inspector
// writes is already on disk by then, so the process leaves without running the teardown.
[[noreturn]] void leave(int code) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
}
}  // namespace

int InspectApp::window(Session& session) {
  if (std::getenv("DISPLAY") == nullptr) {
    throw std::runtime_error("no display (DISPLAY unset): use --render FRAME --out FILE.png, or run under xvfb-run");
  }
  Layers layers = parseLayers(options_.layers);
  mrpt::gui::CDisplayWindow3D win("lidarseg-inspect: " + fs::path(options_.input).filename().string(),
                                  static_cast<unsigned>(options_.width), static_cast<unsigned>(options_.height));
  win.wait_for_GL_context(5.0);
  std::size_t index = options_.frame;
  double zoom = 1.0;
  bool playing = false, help = false, dirty = true;
  std::string number, message;
  cv::Mat shown;
  const auto show = [&] {
    inspect::Drawing d = session.draw(index, layers);
    d.view_half_width_m *= zoom;
    if (!number.empty()) d.status.push_back("> " + number);
    if (!message.empty()) d.status.push_back(message);
    if (help) {
      for (const std::string& k : keyHelp()) d.status.push_back(k);
    } else {
      d.status.push_back("h: keys");
    }
    shown = inspect::renderPng(d, cv::Size(options_.width, options_.height));
    win.setImageView(mrpt::img::CImage(shown, mrpt::img::DEEP_COPY));
    win.forceRepaint();
    dirty = false;
  };
  const auto go = [&](long long target) {
    if (target < 0) target = 0;
    try {
      session.frame(static_cast<std::size_t>(target));
      index = static_cast<std::size_t>(target);
    } catch (const std::out_of_range&) {
      index = session.scansRead() - 1;
      playing = false;
    } catch (const std::exception& e) {  // an unreadable part of the log: say so, stay
      message = e.what();
      playing = false;
    }
    dirty = true;
  };
  const auto tune = [&](auto&& change, const std::string& what) {
    inspect::InspectorParams p = session.params();
    change(p);
    try {
      session.setParams(p);
      message = what;
    } catch (const std::invalid_argument& e) {
      message = std::string("rejected: ") + e.what();
    }
    dirty = true;
  };

  if (!options_.screenshot_out.empty()) {
    show();
    // Give the window time to draw, then capture what it shows.
    win.captureImagesStart();
    mrpt::img::CImage grabbed;
    bool got = false;
    for (int i = 0; i < 50 && !got; ++i) {
      win.forceRepaint();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      got = win.getLastWindowImage(grabbed) && grabbed.getWidth() > 0;
      if (got) {
        cv::Mat m = grabbed.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
        cv::Scalar mean, sd;
        cv::meanStdDev(m, mean, sd);
        got = sd[0] + sd[1] + sd[2] > 1.0;  // an all-black grab (some GL drivers) is no screenshot
      }
    }
    // Stop grabbing and let the GUI thread finish its frame before the window goes away.
    win.captureImagesStop();
    win.forceRepaint();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (got) {
      cv::Mat rgb = grabbed.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
      writeFileAtomically(options_.screenshot_out, encodePng(rgb));
      std::cout << "screenshot of the window (scan " << index << ") written to " << options_.screenshot_out << "\n";
      leave(0);
    }
    std::cerr << "lidarseg-inspect: the GL driver gave no window image; writing the picture the window shows\n";
    writeFileAtomically(options_.screenshot_out, encodePng(shown));
    leave(0);
  }

  auto last_play = std::chrono::steady_clock::now();
  while (win.isOpen()) {
    if (dirty) show();
    if (win.keyHit()) {
      mrpt::gui::mrptKeyModifier mod = mrpt::gui::MRPTKMOD_NONE;
      const int key = win.getPushedKey(&mod);
      const bool shift = (mod & mrpt::gui::MRPTKMOD_SHIFT) != 0;
      const long long step = shift ? 10 : 1;
      message.clear();
      if (key >= '0' && key <= '9' && number.size() < 12) {
        number += static_cast<char>(key);
        dirty = true;
        continue;
      }
      const int k = (key < 256) ? std::toupper(key) : key;
      switch (k) {
        case 'N': case mrpt::gui::MRPTK_RIGHT: go(static_cast<long long>(index) + step); break;
        case 'B': case mrpt::gui::MRPTK_LEFT: go(static_cast<long long>(index) - step); break;
        case mrpt::gui::MRPTK_HOME: go(0); break;
        case mrpt::gui::MRPTK_END: go(static_cast<long long>(session.countAll()) - 1); break;
        case 'G': if (!number.empty()) go(std::stoll(number)); number.clear(); break;
        case 'T':
          if (!number.empty()) go(static_cast<long long>(session.indexAtTime(session.frame(0).stamp_s + std::stod(number))));
          number.clear();
          break;
        case ' ': playing = !playing; dirty = true; break;
        case 'R': layers.raw_points = !layers.raw_points; dirty = true; break;
        case 'Z': layers.levels[0] = !layers.levels[0]; dirty = true; break;
        case 'X': layers.levels[1] = !layers.levels[1]; dirty = true; break;
        case 'C': layers.levels[2] = !layers.levels[2]; dirty = true; break;
        case 'V': layers.levels[3] = !layers.levels[3]; dirty = true; break;
        case 'I': layers.indices = !layers.indices; dirty = true; break;
        case 'K': layers.predicted = !layers.predicted; dirty = true; break;
        case 'M': layers.matches = !layers.matches; dirty = true; break;
        case 'F': layers.features = !layers.features; dirty = true; break;
        case 'O': layers.trajectory = !layers.trajectory; dirty = true; break;
        case 'A': layers.camera = !layers.camera; dirty = true; break;
        case 'U': zoom = std::max(0.1, zoom / 1.25); dirty = true; break;
        case 'D': zoom = std::min(10.0, zoom * 1.25); dirty = true; break;
        case 'H': help = !help; dirty = true; break;
        case '[': case ']':
          tune([&](auto& p) { p.odometry.segmentation.wall_danielsson.threshold_m *= (k == ']' ? 1.1 : 1 / 1.1); },
               "W-D threshold " + std::to_string(session.params().odometry.segmentation.wall_danielsson.threshold_m *
                                                 (k == ']' ? 1.1 : 1 / 1.1)) + " m");
          break;
        case ';': case '\'':
          tune([&](auto& p) {
            const double f = k == '\'' ? 1.1 : 1 / 1.1;
            p.odometry.segmentation.cascade.first_fusion.max_line_distance_m *= f;
            p.odometry.segmentation.cascade.second_fusion.max_line_distance_m *= f;
          }, "fusion line distance x" + std::string(k == '\'' ? "1.1" : "1/1.1"));
          break;
        case ',': case '.':
          tune([&](auto& p) { p.odometry.segmentation.cascade.erosion.min_length_m *= (k == '.' ? 1.1 : 1 / 1.1); },
               "erosion length x" + std::string(k == '.' ? "1.1" : "1/1.1"));
          break;
        case '-': case '=':
          tune([&](auto& p) { p.odometry.matcher.cog_gate_m *= (k == '=' ? 1.1 : 1 / 1.1); },
               "matcher COG gate x" + std::string(k == '=' ? "1.1" : "1/1.1"));
          break;
        case 'S':
          try {
            session.params().saveIni(options_.save_path);
            message = "parameters saved to " + options_.save_path;
          } catch (const std::exception& e) {
            message = std::string("not saved: ") + e.what();
          }
          dirty = true;
          break;
        case 'Q': case mrpt::gui::MRPTK_ESCAPE:
          std::cout << "quit at scan " << index << "\n";
          leave(0);
        default: break;
      }
    }
    if (playing && std::chrono::steady_clock::now() - last_play > std::chrono::milliseconds(100)) {
      last_play = std::chrono::steady_clock::now();
      go(static_cast<long long>(index) + 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(15));
  }
  leave(0);
}

}  // namespace lidarseg::apps
