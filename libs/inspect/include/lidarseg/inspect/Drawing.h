#pragma once
/// @file Drawing.h
/// What lidarseg-inspect shows of one scan, as a list of plain primitives in metres (frame
/// of the current sensor: x forward, y left). The window, the PNG and the SVG renderers
/// all draw this same list, so a screenshot, a --render and a report picture agree.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "lidarseg/report/Palette.h"

namespace lidarseg::inspect {

/// sRGB colour, 0..255: the palette's, shared with every chart of the tools.
using Rgb = report::Rgb;

/// Points of one colour (size in pixels).
struct PointLayer {
  std::vector<Eigen::Vector2d> points;
  Rgb colour;
  int size_px = 2;
};

/// Line segments of one colour (width in pixels).
struct LineLayer {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> lines;
  Rgb colour;
  int width_px = 2;
};

/// A circle (radius in metres) or a text label at a position.
struct Circle {
  Eigen::Vector2d centre;
  double radius_m = 0.2;
  Rgb colour;
};
struct Label {
  Eigen::Vector2d at;
  std::string text;
  Rgb colour;
};

/// A line of the legend: what a colour stands for.
struct LegendEntry {
  std::string name;
  Rgb colour;
};

/// One picture: layers drawn in order, then circles and labels, the status lines on top,
/// the legend (top right) and a scale bar (bottom left), and the camera image (with its ROI
/// boxes drawn) in the bottom-right corner when there is one.
struct Drawing {
  std::vector<PointLayer> points;
  std::vector<LineLayer> lines;
  std::vector<Circle> circles;
  std::vector<Label> labels;
  /// Lines of text at the top of the picture (status line, keys).
  std::vector<std::string> status;
  /// What each colour shown stands for.
  std::vector<LegendEntry> legend;
  /// Half-width of the square area shown around the sensor (m).
  double view_half_width_m = 10.0;
  /// Camera image (BGR) with its ROI boxes, empty when the scan has none.
  cv::Mat camera;
};

/// Raster picture (BGR), `size` pixels, the sensor at the centre, x to the right.
cv::Mat renderPng(const Drawing& drawing, const cv::Size& size);

/// The same picture as an SVG document (the camera image embedded as a PNG data URI).
std::string renderSvg(const Drawing& drawing, const cv::Size& size);

}  // namespace lidarseg::inspect
