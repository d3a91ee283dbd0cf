#pragma once
// Private to lidarseg::apps: the pictures of a run (trajectories, timing histograms,
// per-run errors) as PNG images drawn with OpenCV.

#include <string>
#include <vector>

namespace lidarseg::apps {

/// A named series of points (x, y) drawn in one colour (B, G, R).
struct PlotSeries {
  std::string name;
  int blue = 0, green = 0, red = 0;
  std::vector<double> x, y;
  bool markers = false;  ///< dots instead of a polyline
};

/// Draws the series on equal-scale axes (trajectories, metres) with a legend, a grid and a
/// scale bar. Returns the PNG bytes.
std::string plotTrajectoriesPng(const std::vector<PlotSeries>& series, const std::string& title);

/// Draws histograms of positive samples (e.g. times in microseconds) on a logarithmic x
/// axis, one per series (x holds the samples, y is ignored). Returns the PNG bytes.
std::string plotHistogramsPng(const std::vector<PlotSeries>& series, const std::string& title,
                              const std::string& x_label);

/// Draws y against x (independent scales), lines or markers. Returns the PNG bytes.
std::string plotXYPng(const std::vector<PlotSeries>& series, const std::string& title,
                      const std::string& x_label, const std::string& y_label);

}  // namespace lidarseg::apps
