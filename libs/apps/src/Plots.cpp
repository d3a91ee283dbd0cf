#include "Plots.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "lidarseg/vision/ImageFile.h"

extern char** environ;

namespace lidarseg::apps {

using vision::encodePng;

namespace {

namespace fs = std::filesystem;

// A scratch folder removed with everything in it when the plot is done.
class ScratchFolder {
 public:
  ScratchFolder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/lidarseg-plot.XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("cannot make a scratch folder for a plot: " + std::string(std::strerror(errno)));
    }
    path_ = pattern;
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// gnuplot's quoting of a text: single quotes, a quote doubled.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string rgb(const PlotSeries& s) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", s.colour.r, s.colour.g, s.colour.b);
  return buf;
}

// Runs gnuplot on `script` (which writes `png`) and returns the PNG's bytes.
std::string runGnuplot(const ScratchFolder& dir, const std::string& script) {
  const std::string script_path = dir.file("plot.gp"), log_path = dir.file("gnuplot.log");
  std::ofstream(script_path) << script;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::string program = "gnuplot";
  char* argv[] = {program.data(), const_cast<char*>(script_path.c_str()), nullptr};
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  if (spawned == 0) {
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (spawned != 0 || (WIFEXITED(status) && WEXITSTATUS(status) == 127)) {
    throw std::runtime_error("gnuplot is not installed (Debian package gnuplot-nox; ./run.sh deps)");
  }
  std::ifstream png(dir.file("plot.png"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(png)), std::istreambuf_iterator<char>());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty()) {
    std::ifstream log(log_path);
    std::string first;
    std::getline(log, first);
    throw std::runtime_error("gnuplot failed to draw a plot: " + first);
  }
  return bytes;
}

// The common settings: one size and font for every picture, legend inside the frame on an
// opaque box, a light grid, plain tick labels (no -0, no 1e+03).
std::string preamble(const ScratchFolder& dir, const std::string& title, const std::string& x_label,
                     const std::string& y_label) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1000,800 enhanced font 'DejaVu Sans,12' linewidth 1.5\n"
     << "set output " << quoted(dir.file("plot.png")) << "\n"
     << "set encoding utf8\n"
     << "set title " << quoted(title) << " noenhanced\n"
     << "set xlabel " << quoted(x_label) << " noenhanced\n"
     << "set ylabel " << quoted(y_label) << " noenhanced\n"
     << "set grid lc rgb '#dddddd'\n"
     << "set key inside top right box opaque noenhanced samplen 2\n"
     << "set format x '%h'\nset format y '%h'\n"
     << "set datafile missing 'nan'\n";
  return gp.str();
}

// Writes each series to DIR/seriesK.dat ("x y" rows) and returns the plot command.
std::string plotCommand(const ScratchFolder& dir, const std::vector<PlotSeries>& series) {
  std::ostringstream plot;
  plot << "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const std::string data = dir.file("series" + std::to_string(k) + ".dat");
    std::ofstream out(data);
    out << std::setprecision(9);
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) out << s.x[i] << ' ' << s.y[i] << '\n';
    }
    plot << (k ? ", " : "") << quoted(data) << " using 1:2 " << gnuplotWith(s.style) << " lc rgb '" << rgb(s)
         << "' title " << quoted(s.name);
  }
  return plot.str() + "\n";
}

}  // namespace

std::string gnuplotWith(PlotStyle style) {
  switch (style) {
    case PlotStyle::kMarkers: return "with points pt 7 ps 1.3";
    case PlotStyle::kSteps: return "with steps lw 2";
    case PlotStyle::kLines: break;
  }
  return "with lines lw 2";
}

std::string plotTrajectoriesPng(const std::vector<PlotSeries>& series, const std::string& title) {
  ScratchFolder dir;
  std::string gp = preamble(dir, title, "x (m)", "y (m)");
  gp += "set size ratio -1\n";  // one metre is as long on both axes
  return runGnuplot(dir, gp + plotCommand(dir, series));
}

std::vector<PlotSeries> histogramShares(const std::vector<PlotSeries>& series, int bins) {
  // Logarithmic bins over every series' positive samples; each series' share per bin.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const PlotSeries& s : series) {
    for (double v : s.x) {
      if (v > 0.0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  if (!(lo <= hi)) lo = 1.0, hi = 10.0;
  const double l0 = std::log10(lo), l1 = std::max(std::log10(hi), l0 + 1e-3);
  bins = std::max(bins, 1);
  const double w = (l1 - l0) / bins;
  std::vector<PlotSeries> shares;
  for (const PlotSeries& s : series) {
    PlotSeries h = s;
    h.style = PlotStyle::kSteps;  // each share held across its bin, from the left edge
    h.x.assign(static_cast<std::size_t>(bins) + 1, 0.0);
    h.y.assign(static_cast<std::size_t>(bins) + 1, 0.0);
    std::size_t n = 0;
    for (double v : s.x) {
      if (!(v > 0.0) || !std::isfinite(v)) continue;
      ++h.y[static_cast<std::size_t>(std::clamp(static_cast<int>((std::log10(v) - l0) / w), 0, bins - 1))];
      ++n;
    }
    for (int b = 0; b <= bins; ++b) {
      h.x[static_cast<std::size_t>(b)] = std::pow(10.0, l0 + w * b);  // left edge of bin b
      if (n > 0) h.y[static_cast<std::size_t>(b)] /= static_cast<double>(n);
    }
    shares.push_back(std::move(h));
  }
  return shares;
}

std::string plotHistogramsPng(const std::vector<PlotSeries>& series, const std::string& title,
                              const std::string& x_label) {
  constexpr int kBins = 60;
  const std::vector<PlotSeries> shares = histogramShares(series, kBins);
  ScratchFolder dir;
  std::string gp = preamble(dir, title, x_label + " (log scale)", "share of scans");
  gp += "set logscale x 10\nset yrange [0:*]\nset format x '%g'\n";
  return runGnuplot(dir, gp + plotCommand(dir, shares));
}

std::string plotXYPng(const std::vector<PlotSeries>& series, const std::string& title,
                      const std::string& x_label, const std::string& y_label, bool integer_x) {
  ScratchFolder dir;
  std::string gp = preamble(dir, title, x_label, y_label);
  gp += "set offsets graph 0.03, graph 0.03, graph 0.05, 0\n";
  if (integer_x) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const PlotSeries& s : series) {
      for (double v : s.x) {
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
    }
    const double span = lo <= hi ? hi - lo : 1.0;
    const long step = std::max(1L, static_cast<long>(std::ceil(span / 12.0)));
    gp += "set xtics " + std::to_string(step) + "\nset format x '%.0f'\nset mxtics 1\n";
  }
  return runGnuplot(dir, gp + plotCommand(dir, series));
}

std::string scanFeaturesPng(const ScanPicture& scan, const std::string& title) {
  constexpr int kPanel = 560, kTop = 40;
  cv::Mat img(kPanel + kTop, 2 * kPanel, CV_8UC3, cv::Scalar(255, 255, 255));
  // One scale for both panels, fitting every point (and the robot) with a margin.
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  for (const auto& [x, y] : scan.points) {
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  const double span = std::max({x1 - x0, y1 - y0, 1.0}) * 1.08;
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const double scale = kPanel / span;
  auto px = [&](double x, double y, int panel) {
    return cv::Point(static_cast<int>(std::lround(panel * kPanel + kPanel / 2 + (x - cx) * scale)),
                     static_cast<int>(std::lround(kTop + kPanel / 2 - (y - cy) * scale)));
  };
  cv::line(img, cv::Point(kPanel, kTop), cv::Point(kPanel, kTop + kPanel), cv::Scalar(180, 180, 180), 1);
  for (const auto& [x, y] : scan.points) cv::circle(img, px(x, y, 0), 1, cv::Scalar(60, 60, 60), cv::FILLED);
  for (const auto& s : scan.segments) {
    cv::line(img, px(s[0], s[1], 1), px(s[2], s[3], 1), cv::Scalar(160, 90, 0), 2, cv::LINE_AA);
  }
  for (const auto& j : scan.door_jambs) {
    cv::line(img, px(j[0], j[1], 1), px(j[2], j[3], 1), cv::Scalar(0, 0, 220), 1, cv::LINE_AA);
  }
  for (const auto& [x, y] : scan.doors) cv::circle(img, px(x, y, 1), 9, cv::Scalar(0, 0, 230), 2, cv::LINE_AA);
  for (const auto& [x, y] : scan.corners) cv::circle(img, px(x, y, 1), 9, cv::Scalar(0, 170, 0), 2, cv::LINE_AA);
  for (int panel = 0; panel < 2; ++panel) {
    const cv::Point r = px(0, 0, panel);
    cv::line(img, r - cv::Point(7, 7), r + cv::Point(7, 7), cv::Scalar(0, 0, 255), 2);
    cv::line(img, r - cv::Point(7, -7), r + cv::Point(7, -7), cv::Scalar(0, 0, 255), 2);
  }
  cv::putText(img, title, cv::Point(10, 26), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "raw scan", cv::Point(10, kTop + 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::putText(img, "segments, doors (red), corners (green)", cv::Point(kPanel + 10, kTop + 20),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Scale bar: 1 m.
  const cv::Point b0(20, kTop + kPanel - 20);
  cv::line(img, b0, b0 + cv::Point(static_cast<int>(scale), 0), cv::Scalar(0, 0, 0), 2);
  cv::putText(img, "1 m", b0 + cv::Point(0, -8), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return encodePng(img);
}

}  // namespace lidarseg::apps
