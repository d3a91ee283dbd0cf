#include "lidarseg/report/Plots.h"
#include "lidarseg/report/OutputFiles.h"

#include <algorithm>
#include <atomic>
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
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace lidarseg::report {

namespace {

namespace fs = std::filesystem;

// A scratch folder removed with everything in it when the plot is done, and by the SIGINT/
// SIGTERM handler if the process is stopped meanwhile (it is registered before it is made).
class ScratchFolder {
 public:
  ScratchFolder() {
    static std::atomic<unsigned long> counter{0};
    const char* tmp = std::getenv("TMPDIR");
    const std::string base = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/lidarseg-plot." +
                             std::to_string(::getpid()) + ".";
    for (int attempt = 0;; ++attempt) {
      path_ = base + std::to_string(counter++);
      registerTemporaryFolder(path_);
      if (::mkdir(path_.c_str(), 0700) == 0) return;
      const int error = errno;
      releaseTemporary(path_);
      if (error != EEXIST || attempt >= 100) {
        throw std::runtime_error("cannot make a scratch folder for a plot ('" + path_ + "'): " + std::strerror(error));
      }
    }
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
    releaseTemporary(path_);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// gnuplot's quoting of a text: single quotes, a quote doubled; a control character (a
// newline in a file name) a space, since it would end the script's line.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') {
      out += "''";
    } else {
      out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? ' ' : c;
    }
  }
  return out + "'";
}

// gnuplot's colour of a palette entry: "#rrggbb".
std::string hex(const Rgb& c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

std::string rgb(const PlotSeries& s) { return hex(s.colour); }

// Why gnuplot drew nothing: what it said (its non-blank lines, trimmed, in one line: its
// messages start with a blank line and the script's line), else how it ended.
std::string gnuplotReason(const std::string& log_path, int status) {
  std::ifstream log(log_path);
  std::string said, line;
  while (std::getline(log, line) && said.size() < 400) {
    const auto first = line.find_first_not_of(" \t\r^");
    if (first == std::string::npos) continue;
    const auto last = line.find_last_not_of(" \t\r");
    said += (said.empty() ? "" : " / ") + line.substr(first, last - first + 1);
  }
  if (!said.empty()) return said;
  if (WIFSIGNALED(status)) return "gnuplot was killed by signal " + std::to_string(WTERMSIG(status)) + " and said nothing";
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    return "gnuplot exited with status " + std::to_string(WEXITSTATUS(status)) + " and said nothing";
  }
  return "gnuplot ended well but wrote no picture";
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
    throw PlotterMissing("gnuplot is not installed (Debian package gnuplot-nox; ./run.sh deps)");
  }
  std::ifstream png(dir.file("plot.png"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(png)), std::istreambuf_iterator<char>());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty()) {
    throw std::runtime_error("gnuplot failed to draw a plot: " + gnuplotReason(log_path, status));
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

// Writes each series to DIR/seriesK.dat ("x y" rows) and returns the plot command. A series
// with no finite point keeps its legend entry, marked "(no data)" (gnuplot refuses a data
// file with no valid point); when no series has one, the frame says "no data" instead of
// gnuplot failing on a plot with nothing to scale.
std::string plotCommand(const ScratchFolder& dir, const std::vector<PlotSeries>& series) {
  std::ostringstream plot;
  plot << "plot ";
  bool any = false;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const std::string data = dir.file("series" + std::to_string(k) + ".dat");
    std::ofstream out(data);
    out << std::setprecision(9);
    std::size_t rows = 0;
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) out << s.x[i] << ' ' << s.y[i] << '\n', ++rows;
    }
    any = any || rows > 0;
    plot << (k ? ", " : "") << (rows > 0 ? quoted(data) + " using 1:2 " : std::string("NaN ")) << gnuplotWith(s.style)
         << " lc rgb '" << rgb(s) << "' title " << quoted(rows > 0 ? s.name : s.name + " (no data)");
  }
  if (series.empty()) plot << "NaN notitle";
  if (any) return plot.str() + "\n";
  return "set label 'no data' at graph 0.5, 0.5 center\nunset logscale\nset xrange [0:1]\nset yrange [0:1]\n" +
         plot.str() + "\n";
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

namespace {

// The scan figure's pixels: the picture's width, each panel's margins (tick labels and the
// y label on the left, the gap to the next panel on the right), the figure's top (its title
// and the panels' titles) and bottom (the x label), the bands above and below the data for
// the legend and the scale bar, and the bounds of a panel's plot height.
constexpr int kFigureWidthPx = 1600;
constexpr int kPanelLeftPx = 80, kPanelRightPx = 30;
constexpr int kFigureTopPx = 95, kFigureBottomPx = 60;
constexpr int kKeyBandPx = 66, kBarBandPx = 44;  // the legend takes up to two rows
constexpr int kBarInsetPx = 20;                    // the scale bar from the frame's left edge
constexpr int kMinPlotPx = 300, kMaxPlotPx = 1000;
// The data's margin (share of its span on each side), the smallest span shown (m) and the
// scale bar's length as a share of a panel's width.
constexpr double kMarginShare = 0.05, kMinSpanM = 2.0, kBarShare = 1.0 / 6.0;

// The largest 1, 2 or 5 times a power of ten not above `m` (> 0).
double roundLength(double m) {
  const double p = std::pow(10.0, std::floor(std::log10(m)));
  for (double k : {5.0, 2.0}) {
    if (k * p <= m) return k * p;
  }
  return p;
}

// Writes "x y" rows to `path`: one point per row (writePoints), or each quadruple as a
// two-point line followed by a blank line, gnuplot's separator of polylines (writeLines).
void writePoints(const std::string& path, const std::vector<std::pair<double, double>>& points) {
  std::ofstream out(path);
  out << std::setprecision(9);
  for (const auto& [x, y] : points) out << x << ' ' << y << '\n';
}
void writeLines(const std::string& path, const std::vector<std::array<double, 4>>& lines) {
  std::ofstream out(path);
  out << std::setprecision(9);
  for (const auto& l : lines) out << l[0] << ' ' << l[1] << '\n' << l[2] << ' ' << l[3] << "\n\n";
}

// "1 door", "2 doors".
std::string counted(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

}  // namespace

ScanFigureLayout scanFigureLayout(const ScanPicture& scan) {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // the sensor is always shown
  auto take = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  };
  for (const auto& [x, y] : scan.points) take(x, y);
  for (const auto& l : scan.segments) take(l[0], l[1]), take(l[2], l[3]);
  for (const auto& l : scan.door_jambs) take(l[0], l[1]), take(l[2], l[3]);
  for (const auto& [x, y] : scan.doors) take(x, y);
  for (const auto& [x, y] : scan.corners) take(x, y);
  const double span_x = std::max(x1 - x0, kMinSpanM) * (1.0 + 2.0 * kMarginShare);
  const double span_y = std::max(y1 - y0, kMinSpanM) * (1.0 + 2.0 * kMarginShare);
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const int plot_w = kFigureWidthPx / 2 - kPanelLeftPx - kPanelRightPx;
  const int bands = kKeyBandPx + kBarBandPx;
  const int data_h = std::clamp(static_cast<int>(std::lround(plot_w * span_y / span_x)), kMinPlotPx - bands,
                                kMaxPlotPx - bands);
  // One scale (pixels per metre) fitting the data in plot_w x data_h; the ranges widened to
  // the plot's pixels, so a metre is as long on both axes.
  const double scale = std::min(plot_w / span_x, data_h / span_y);
  ScanFigureLayout layout;
  layout.width_px = kFigureWidthPx;
  layout.height_px = data_h + bands + kFigureTopPx + kFigureBottomPx;
  layout.plot_left_px[0] = kPanelLeftPx;
  layout.plot_left_px[1] = kFigureWidthPx / 2 + kPanelLeftPx;
  layout.plot_top_px = kFigureTopPx;
  layout.plot_width_px = plot_w;
  layout.plot_height_px = data_h + bands;
  layout.x_min_m = cx - 0.5 * plot_w / scale;
  layout.x_max_m = cx + 0.5 * plot_w / scale;
  layout.y_min_m = cy - (0.5 * data_h + kBarBandPx) / scale;
  layout.y_max_m = cy + (0.5 * data_h + kKeyBandPx) / scale;
  layout.scale_bar_m = roundLength(kBarShare * plot_w / scale);
  return layout;
}

std::string scanFeaturesPng(const ScanPicture& scan, const std::string& title) {
  const ScanFigureLayout L = scanFigureLayout(scan);
  ScratchFolder dir;
  const std::string points = dir.file("points.dat"), segments = dir.file("segments.dat"),
                    jambs = dir.file("jambs.dat"), doors = dir.file("doors.dat"), corners = dir.file("corners.dat"),
                    robot = dir.file("robot.dat");
  writePoints(points, scan.points);
  writeLines(segments, scan.segments);
  writeLines(jambs, scan.door_jambs);
  writePoints(doors, scan.doors);
  writePoints(corners, scan.corners);
  writePoints(robot, {{0.0, 0.0}});

  const double W = L.width_px, H = L.height_px;
  const double px_per_m = L.plot_width_px / (L.x_max_m - L.x_min_m);
  const double bar_x = L.x_min_m + kBarInsetPx / px_per_m, bar_y = L.y_min_m + 0.5 * kBarBandPx / px_per_m;
  std::ostringstream gp;
  gp << std::setprecision(9);
  gp << "set terminal pngcairo size " << L.width_px << ',' << L.height_px
     << " enhanced font 'DejaVu Sans,12' linewidth 1.5\n"
     << "set output " << quoted(dir.file("plot.png")) << "\n"
     << "set encoding utf8\n"
     << "set multiplot title " << quoted(title) << " noenhanced font ',14'\n"
     << "set xrange [" << L.x_min_m << ':' << L.x_max_m << "]\nset yrange [" << L.y_min_m << ':' << L.y_max_m << "]\n"
     << "set xlabel 'x (m, sensor frame)'\nset ylabel 'y (m, sensor frame)'\n"
     << "set grid lc rgb '#dddddd'\n"
     << "set format x '%h'\nset format y '%h'\n"
     << "set key inside top left horizontal box opaque noenhanced samplen 1.5 width 1\n"
     << "set tmargin at screen " << 1.0 - L.plot_top_px / H << "\nset bmargin at screen "
     << 1.0 - (L.plot_top_px + L.plot_height_px) / H << "\n"
     << "set arrow 1 from " << bar_x << ',' << bar_y << " to " << bar_x + L.scale_bar_m << ',' << bar_y
     << " nohead lw 3 lc rgb 'black' front\n"
     << "set label 1 '" << L.scale_bar_m << " m' at " << bar_x + L.scale_bar_m << ',' << bar_y
     << " offset 0.8,0 left front\n";
  const std::string robot_plot = quoted(robot) + " using 1:2 with points pt 2 ps 3 lw 2.5 lc rgb '" +
                                 hex(kRobotColour) + "' title 'robot'";
  // Left: the raw points.
  gp << "set lmargin at screen " << L.plot_left_px[0] / W << "\nset rmargin at screen "
     << (L.plot_left_px[0] + L.plot_width_px) / W
     << "\nset title 'raw scan: " << counted(scan.points.size(), "point") << "'\n"
     << "plot ";
  if (!scan.points.empty()) {
    gp << quoted(points) << " using 1:2 with points pt 7 ps 0.45 lc rgb '" << hex(kScanPointColour)
       << "' title 'scan points', ";
  }
  gp << robot_plot << "\n";
  // Right: the segments, doors with their jambs, corners.
  gp << "set lmargin at screen " << L.plot_left_px[1] / W << "\nset rmargin at screen "
     << (L.plot_left_px[1] + L.plot_width_px) / W
     << "\nset title '" << counted(scan.segments.size(), "segment") << ", " << counted(scan.doors.size(), "door")
     << ", " << counted(scan.corners.size(), "corner") << "'\n"
     << "plot ";
  if (!scan.segments.empty()) {
    gp << quoted(segments) << " using 1:2 with lines lw 2.5 lc rgb '" << hex(kLidarsegColour)
       << "' title 'segments', ";
  }
  if (!scan.door_jambs.empty()) {
    gp << quoted(jambs) << " using 1:2 with lines lw 1.5 dt 2 lc rgb '" << hex(kDoorColour)
       << "' title 'door jambs', ";
  }
  if (!scan.doors.empty()) {
    gp << quoted(doors) << " using 1:2 with points pt 6 ps 2.5 lw 2 lc rgb '" << hex(kDoorColour)
       << "' title 'door', ";
  }
  if (!scan.corners.empty()) {
    gp << quoted(corners) << " using 1:2 with points pt 6 ps 2.5 lw 2 lc rgb '" << hex(kCornerColour)
       << "' title 'corner', ";
  }
  gp << robot_plot << "\nunset multiplot\n";
  return runGnuplot(dir, gp.str());
}

ScanPicture scanPictureOf(const Segmentation& segmentation, CascadeLevel level, const std::vector<Feature>& features) {
  ScanPicture pic;
  for (const auto& q : segmentation.points) {
    if (std::isfinite(q.x())) pic.points.emplace_back(q.x(), q.y());
  }
  for (const Segment& sg : segmentation.level(level).segments) {
    pic.segments.push_back({sg.start.x(), sg.start.y(), sg.end.x(), sg.end.y()});
  }
  for (const Feature& f : features) {
    if (isDoor(f.type)) {
      pic.doors.emplace_back(f.position.x(), f.position.y());
      pic.door_jambs.push_back({f.jamb_a.x(), f.jamb_a.y(), f.jamb_b.x(), f.jamb_b.y()});
    } else {
      pic.corners.emplace_back(f.position.x(), f.position.y());
    }
  }
  return pic;
}

}  // namespace lidarseg::report
