#include "Plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::apps {

using vision::encodePng;

namespace {

constexpr int kWidth = 1000, kHeight = 800;
constexpr int kLeft = 90, kRight = 30, kTop = 50, kBottom = 70;

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool valid() const { return lo <= hi; }
  void pad(double fraction, double min_span) {
    if (!valid()) {
      lo = 0.0;
      hi = 1.0;
    }
    double span = std::max(hi - lo, min_span);
    const double mid = 0.5 * (lo + hi);
    span *= 1.0 + 2.0 * fraction;
    lo = mid - 0.5 * span;
    hi = mid + 0.5 * span;
  }
};

cv::Scalar colour(const PlotSeries& s) { return cv::Scalar(s.blue, s.green, s.red); }

std::string label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// A "nice" tick step for a span.
double niceStep(double span, int ticks) {
  const double raw = span / std::max(ticks, 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10.0 * mag;
}

struct Axes {
  Range x, y;
  int x0 = kLeft, x1 = kWidth - kRight, y0 = kHeight - kBottom, y1 = kTop;
  cv::Point map(double vx, double vy) const {
    const double u = (vx - x.lo) / (x.hi - x.lo);
    const double v = (vy - y.lo) / (y.hi - y.lo);
    return {static_cast<int>(std::lround(x0 + u * (x1 - x0))), static_cast<int>(std::lround(y0 + v * (y1 - y0)))};
  }
};

void drawFrame(cv::Mat& img, const Axes& a, const std::string& title, const std::string& x_label,
               const std::string& y_label, bool log_x) {
  const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);
  const double sx = niceStep(a.x.hi - a.x.lo, 8), sy = niceStep(a.y.hi - a.y.lo, 8);
  for (double v = std::ceil(a.x.lo / sx) * sx; v <= a.x.hi; v += sx) {
    const cv::Point p = a.map(v, a.y.lo);
    cv::line(img, {p.x, a.y0}, {p.x, a.y1}, grid, 1);
    cv::putText(img, label(log_x ? std::pow(10.0, v) : v), {p.x - 20, a.y0 + 22}, cv::FONT_HERSHEY_SIMPLEX,
                0.45, ink, 1, cv::LINE_AA);
  }
  for (double v = std::ceil(a.y.lo / sy) * sy; v <= a.y.hi; v += sy) {
    const cv::Point p = a.map(a.x.lo, v);
    cv::line(img, {a.x0, p.y}, {a.x1, p.y}, grid, 1);
    cv::putText(img, label(v), {8, p.y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
  }
  cv::rectangle(img, {a.x0, a.y1}, {a.x1, a.y0}, ink, 1);
  cv::putText(img, title, {a.x0, 32}, cv::FONT_HERSHEY_SIMPLEX, 0.7, ink, 1, cv::LINE_AA);
  cv::putText(img, x_label, {(a.x0 + a.x1) / 2 - 60, kHeight - 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, ink, 1,
              cv::LINE_AA);
  cv::putText(img, y_label, {8, a.y1 - 12}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
}

void drawLegend(cv::Mat& img, const std::vector<PlotSeries>& series, const Axes& a) {
  int y = a.y1 + 25;
  for (const auto& s : series) {
    cv::line(img, {a.x1 - 200, y - 5}, {a.x1 - 170, y - 5}, colour(s), 3, cv::LINE_AA);
    cv::putText(img, s.name, {a.x1 - 160, y}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(40, 40, 40), 1,
                cv::LINE_AA);
    y += 22;
  }
}

void drawSeries(cv::Mat& img, const Axes& a, const PlotSeries& s) {
  std::vector<cv::Point> pts;
  pts.reserve(s.x.size());
  for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
    if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) pts.push_back(a.map(s.x[i], s.y[i]));
  }
  if (s.markers) {
    for (const auto& p : pts) cv::circle(img, p, 4, colour(s), cv::FILLED, cv::LINE_AA);
  } else if (pts.size() >= 2) {
    cv::polylines(img, pts, false, colour(s), 2, cv::LINE_AA);
  }
}

}  // namespace

std::string plotTrajectoriesPng(const std::vector<PlotSeries>& series, const std::string& title) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  Axes a;
  for (const auto& s : series) {
    for (double v : s.x) a.x.add(v);
    for (double v : s.y) a.y.add(v);
  }
  a.x.pad(0.05, 1.0);
  a.y.pad(0.05, 1.0);
  // Equal scales: widen the narrower range.
  const double px = (a.x.hi - a.x.lo) / (a.x1 - a.x0), py = (a.y.hi - a.y.lo) / (a.y0 - a.y1);
  const double scale = std::max(px, py);
  const double cx = 0.5 * (a.x.lo + a.x.hi), cy = 0.5 * (a.y.lo + a.y.hi);
  a.x = {cx - 0.5 * scale * (a.x1 - a.x0), cx + 0.5 * scale * (a.x1 - a.x0)};
  a.y = {cy - 0.5 * scale * (a.y0 - a.y1), cy + 0.5 * scale * (a.y0 - a.y1)};
  drawFrame(img, a, title, "x (m)", "y (m)", false);
  for (const auto& s : series) drawSeries(img, a, s);
  for (const auto& s : series) {  // start (circle) and end (square) of each
    if (s.x.empty()) continue;
    cv::circle(img, a.map(s.x.front(), s.y.front()), 6, colour(s), 2, cv::LINE_AA);
    const cv::Point e = a.map(s.x.back(), s.y.back());
    cv::rectangle(img, {e.x - 5, e.y - 5}, {e.x + 5, e.y + 5}, colour(s), 2, cv::LINE_AA);
  }
  drawLegend(img, series, a);
  return encodePng(img);
}

std::string plotHistogramsPng(const std::vector<PlotSeries>& series, const std::string& title,
                              const std::string& x_label) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  Axes a;
  for (const auto& s : series) {
    for (double v : s.x) {
      if (v > 0.0) a.x.add(std::log10(v));
    }
  }
  a.x.pad(0.02, 0.5);
  constexpr int kBins = 80;
  const double w = (a.x.hi - a.x.lo) / kBins;
  std::vector<std::vector<double>> counts;
  double peak = 0.0;
  for (const auto& s : series) {
    std::vector<double> c(kBins, 0.0);
    for (double v : s.x) {
      if (!(v > 0.0)) continue;
      const int b = std::clamp(static_cast<int>((std::log10(v) - a.x.lo) / w), 0, kBins - 1);
      c[b] += 1.0;
    }
    for (double& v : c) v = s.x.empty() ? 0.0 : v / static_cast<double>(s.x.size());
    peak = std::max(peak, *std::max_element(c.begin(), c.end()));
    counts.push_back(std::move(c));
  }
  a.y = {0.0, std::max(peak, 1e-9) * 1.1};
  drawFrame(img, a, title, x_label + " (log scale)", "share of scans", true);
  for (std::size_t k = 0; k < series.size(); ++k) {
    for (int b = 0; b < kBins; ++b) {
      if (counts[k][b] <= 0.0) continue;
      const cv::Point p0 = a.map(a.x.lo + b * w, 0.0), p1 = a.map(a.x.lo + (b + 1) * w, counts[k][b]);
      cv::rectangle(img, p0, p1, colour(series[k]), cv::FILLED);
    }
  }
  drawLegend(img, series, a);
  return encodePng(img);
}

std::string plotXYPng(const std::vector<PlotSeries>& series, const std::string& title,
                      const std::string& x_label, const std::string& y_label) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  Axes a;
  for (const auto& s : series) {
    for (double v : s.x) a.x.add(v);
    for (double v : s.y) a.y.add(v);
  }
  a.x.pad(0.03, 1.0);
  a.y.add(0.0);
  a.y.pad(0.05, 1e-3);
  drawFrame(img, a, title, x_label, y_label, false);
  for (const auto& s : series) drawSeries(img, a, s);
  drawLegend(img, series, a);
  return encodePng(img);
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
