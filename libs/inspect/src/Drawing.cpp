#include "lidarseg/inspect/Drawing.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lidarseg/report/Format.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::inspect {

using vision::encodePng;

using report::escapeXml;

namespace {

// Metres (sensor frame) to pixels: the sensor at the centre, x right, y up.
struct View {
  double cx, cy, scale;
  View(const Drawing& d, const cv::Size& size)
      : cx(0.5 * size.width), cy(0.5 * size.height),
        scale(0.5 * std::min(size.width, size.height) / std::max(d.view_half_width_m, 0.1)) {}
  cv::Point2d operator()(const Eigen::Vector2d& p) const { return {cx + scale * p.x(), cy - scale * p.y()}; }
};

cv::Scalar bgr(const Rgb& c) { return cv::Scalar(c.b, c.g, c.r); }

// The scale bar's length (m): the round length drawn 60 to 200 pixels long.
double scaleBarMetres(double pixels_per_metre) {
  for (double m : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    if (m * pixels_per_metre >= 60.0) return m;
  }
  return 100.0;
}

std::string metresText(double m) {
  std::ostringstream os;
  os << m << " m";
  return os.str();
}
constexpr int kStatusLineHeight = 18;
const cv::Scalar kBackground(250, 250, 250);

// Where the camera inset goes: bottom right, a third of the width.
cv::Rect insetRect(const cv::Mat& camera, const cv::Size& size) {
  if (camera.empty()) return {};
  const int w = size.width / 3;
  const int h = static_cast<int>(std::lround(static_cast<double>(w) * camera.rows / std::max(camera.cols, 1)));
  return cv::Rect(size.width - w - 8, size.height - h - 8, w, h);
}

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const auto at = [&](std::size_t j) { return j < bytes.size() ? static_cast<unsigned char>(bytes[j]) : 0u; };
    const unsigned n = (at(i) << 16) | (at(i + 1) << 8) | at(i + 2);
    out += k[(n >> 18) & 63];
    out += k[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? k[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? k[n & 63] : '=';
  }
  return out;
}

std::string hex(const Rgb& c) {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

}  // namespace

cv::Mat renderPng(const Drawing& d, const cv::Size& size) {
  cv::Mat img(size, CV_8UC3, kBackground);
  const View v(d, size);
  // A 1 m grid.
  const int n = static_cast<int>(std::ceil(d.view_half_width_m * std::max(size.width, size.height) /
                                           std::min(size.width, size.height)));
  for (int k = -n; k <= n; ++k) {
    const cv::Scalar grid = k == 0 ? cv::Scalar(200, 200, 200) : cv::Scalar(232, 232, 232);
    cv::line(img, v({double(k), -n - 1.0}), v({double(k), n + 1.0}), grid, 1);
    cv::line(img, v({-n - 1.0, double(k)}), v({n + 1.0, double(k)}), grid, 1);
  }
  for (const LineLayer& layer : d.lines) {
    for (const auto& [a, b] : layer.lines) cv::line(img, v(a), v(b), bgr(layer.colour), layer.width_px, cv::LINE_AA);
  }
  for (const PointLayer& layer : d.points) {
    for (const Eigen::Vector2d& p : layer.points) {
      cv::circle(img, v(p), std::max(layer.size_px / 2, 1), bgr(layer.colour), cv::FILLED);
    }
  }
  for (const Circle& c : d.circles) {
    cv::circle(img, v(c.centre), std::max(3, static_cast<int>(std::lround(c.radius_m * v.scale))), bgr(c.colour), 2,
               cv::LINE_AA);
  }
  for (const Label& l : d.labels) {
    cv::putText(img, l.text, v(l.at) + cv::Point2d(3, -3), cv::FONT_HERSHEY_SIMPLEX, 0.35, bgr(l.colour), 1,
                cv::LINE_AA);
  }
  // The sensor: a small triangle pointing along x.
  std::vector<cv::Point> robot = {v({0.35, 0}), v({-0.15, 0.15}), v({-0.15, -0.15})};
  cv::fillConvexPoly(img, robot, bgr(report::kRobotColour), cv::LINE_AA);
  if (!d.camera.empty()) {
    const cv::Rect r = insetRect(d.camera, size);
    if ((r & cv::Rect(cv::Point(0, 0), size)) == r && r.area() > 0) {
      cv::resize(d.camera, img(r), r.size(), 0, 0, cv::INTER_AREA);
      cv::rectangle(img, r, cv::Scalar(60, 60, 60), 1);
    }
  }
  const int band = kStatusLineHeight * static_cast<int>(d.status.size()) + (d.status.empty() ? 0 : 6);
  if (band > 0) {
    img(cv::Rect(0, 0, size.width, std::min(band, size.height))).setTo(cv::Scalar(45, 45, 45));
    // One font size for every status line, small enough for the longest to fit.
    double font = 0.45;
    for (const std::string& line : d.status) {
      int base = 0;
      const int w = cv::getTextSize(line, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &base).width;
      if (w > size.width - 12) font = std::min(font, std::max(0.25, 0.45 * (size.width - 12) / w));
    }
    for (std::size_t i = 0; i < d.status.size(); ++i) {
      cv::putText(img, d.status[i], cv::Point(6, kStatusLineHeight * static_cast<int>(i + 1)), cv::FONT_HERSHEY_SIMPLEX,
                  font, cv::Scalar(240, 240, 240), 1, cv::LINE_AA);
    }
  }
  // The legend, top right under the status lines.
  if (!d.legend.empty()) {
    int width = 0, base = 0;
    for (const LegendEntry& e : d.legend) {
      width = std::max(width, cv::getTextSize(e.name, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &base).width);
    }
    const int row = 16, x0 = size.width - width - 44, y0 = band + 8;
    const cv::Rect box(x0 - 6, y0 - 4, width + 46, row * static_cast<int>(d.legend.size()) + 8);
    img(box & cv::Rect(cv::Point(0, 0), size)).setTo(cv::Scalar(255, 255, 255));
    cv::rectangle(img, box, cv::Scalar(150, 150, 150), 1);
    for (std::size_t i = 0; i < d.legend.size(); ++i) {
      const int y = y0 + row * static_cast<int>(i) + 10;
      cv::line(img, {x0, y - 4}, {x0 + 26, y - 4}, bgr(d.legend[i].colour), 3, cv::LINE_AA);
      cv::putText(img, d.legend[i].name, {x0 + 32, y}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(30, 30, 30), 1,
                  cv::LINE_AA);
    }
  }
  // The scale bar, bottom left.
  const double metres = scaleBarMetres(v.scale);
  const int length = static_cast<int>(std::lround(metres * v.scale));
  const cv::Point s0(16, size.height - 20), s1(16 + length, size.height - 20);
  cv::line(img, s0, s1, cv::Scalar(20, 20, 20), 2);
  cv::line(img, s0 + cv::Point(0, -5), s0 + cv::Point(0, 5), cv::Scalar(20, 20, 20), 2);
  cv::line(img, s1 + cv::Point(0, -5), s1 + cv::Point(0, 5), cv::Scalar(20, 20, 20), 2);
  cv::putText(img, metresText(metres), s0 + cv::Point(0, -9), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(20, 20, 20),
              1, cv::LINE_AA);
  return img;
}

std::string renderSvg(const Drawing& d, const cv::Size& size) {
  const View v(d, size);
  std::ostringstream os;
  os.precision(5);
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size.width << "\" height=\"" << size.height
     << "\" viewBox=\"0 0 " << size.width << ' ' << size.height << "\">\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"#fafafa\"/>\n";
  for (const LineLayer& layer : d.lines) {
    os << "<g stroke=\"" << hex(layer.colour) << "\" stroke-width=\"" << layer.width_px << "\">\n";
    for (const auto& [a, b] : layer.lines) {
      const auto p = v(a), q = v(b);
      os << "<line x1=\"" << p.x << "\" y1=\"" << p.y << "\" x2=\"" << q.x << "\" y2=\"" << q.y << "\"/>\n";
    }
    os << "</g>\n";
  }
  for (const PointLayer& layer : d.points) {
    os << "<g fill=\"" << hex(layer.colour) << "\">\n";
    for (const Eigen::Vector2d& pt : layer.points) {
      const auto p = v(pt);
      os << "<circle cx=\"" << p.x << "\" cy=\"" << p.y << "\" r=\"" << std::max(layer.size_px / 2, 1) << "\"/>\n";
    }
    os << "</g>\n";
  }
  for (const Circle& c : d.circles) {
    const auto p = v(c.centre);
    os << "<circle cx=\"" << p.x << "\" cy=\"" << p.y << "\" r=\"" << std::max(3.0, c.radius_m * v.scale)
       << "\" fill=\"none\" stroke=\"" << hex(c.colour) << "\" stroke-width=\"2\"/>\n";
  }
  for (const Label& l : d.labels) {
    const auto p = v(l.at);
    os << "<text x=\"" << p.x + 3 << "\" y=\"" << p.y - 3 << "\" font-size=\"10\" fill=\"" << hex(l.colour) << "\">"
       << escapeXml(l.text) << "</text>\n";
  }
  const auto a = v({0.35, 0}), b = v({-0.15, 0.15}), c = v({-0.15, -0.15});
  os << "<polygon points=\"" << a.x << ',' << a.y << ' ' << b.x << ',' << b.y << ' ' << c.x << ',' << c.y
     << "\" fill=\"#c82828\"/>\n";
  if (!d.camera.empty()) {
    const cv::Rect r = insetRect(d.camera, size);
    const std::string png = encodePng(d.camera);
    os << "<image x=\"" << r.x << "\" y=\"" << r.y << "\" width=\"" << r.width << "\" height=\"" << r.height
       << "\" href=\"data:image/png;base64," << base64(png) << "\"/>\n";
  }
  if (!d.status.empty()) {
    os << "<rect x=\"0\" y=\"0\" width=\"" << size.width << "\" height=\""
       << kStatusLineHeight * d.status.size() + 6 << "\" fill=\"#2d2d2d\"/>\n";
    for (std::size_t i = 0; i < d.status.size(); ++i) {
      os << "<text x=\"6\" y=\"" << kStatusLineHeight * (i + 1) - 4
         << "\" font-family=\"monospace\" font-size=\"12\" fill=\"#f0f0f0\" textLength=\"" << size.width - 12
         << "\" lengthAdjust=\"spacingAndGlyphs\">" << escapeXml(d.status[i]) << "</text>\n";
    }
  }
  // The legend (top right) and the scale bar (bottom left), as in renderPng().
  const std::size_t band = d.status.empty() ? 0 : kStatusLineHeight * d.status.size() + 6;
  if (!d.legend.empty()) {
    const int row = 16, width = 230, x0 = size.width - width - 10;
    os << "<rect x=\"" << x0 - 6 << "\" y=\"" << band + 4 << "\" width=\"" << width + 12 << "\" height=\""
       << row * d.legend.size() + 8 << "\" fill=\"#ffffff\" stroke=\"#969696\"/>\n";
    for (std::size_t i = 0; i < d.legend.size(); ++i) {
      const std::size_t y = band + 8 + row * i + 10;
      os << "<line x1=\"" << x0 << "\" y1=\"" << y - 4 << "\" x2=\"" << x0 + 26 << "\" y2=\"" << y - 4 << "\" stroke=\""
         << hex(d.legend[i].colour) << "\" stroke-width=\"3\"/>\n"
         << "<text x=\"" << x0 + 32 << "\" y=\"" << y << "\" font-size=\"11\" fill=\"#1e1e1e\">" << escapeXml(d.legend[i].name)
         << "</text>\n";
    }
  }
  const double metres = scaleBarMetres(v.scale);
  const double length = metres * v.scale, y = size.height - 20.0;
  os << "<path d=\"M16 " << y - 5 << " V" << y + 5 << " M16 " << y << " H" << 16 + length << " M" << 16 + length << ' '
     << y - 5 << " V" << y + 5 << "\" stroke=\"#141414\" stroke-width=\"2\" fill=\"none\"/>\n"
     << "<text x=\"16\" y=\"" << y - 9 << "\" font-size=\"12\" fill=\"#141414\">" << metresText(metres) << "</text>\n";
  os << "</svg>\n";
  return os.str();
}

}  // namespace lidarseg::inspect
