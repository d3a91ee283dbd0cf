#pragma once
// Private to lidarseg::apps: the pictures of a run (trajectories, timing histograms,
// per-run errors) as PNG images drawn by gnuplot (pngcairo); a scan's features with OpenCV.
// @throws std::runtime_error when gnuplot is missing or fails.

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "lidarseg/pipeline/Palette.h"

namespace lidarseg::apps {

/// How a series is drawn.
enum class PlotStyle {
  kLines,    ///< a polyline through the points
  kMarkers,  ///< a dot at each point
  kSteps,    ///< steps: each y held from its x to the next x (histograms' bins)
};

/// gnuplot's `with` clause of a style, e.g. "with steps lw 2".
std::string gnuplotWith(PlotStyle style);

/// A named series of points (x, y) drawn in one colour: one of the palette's
/// (lidarseg/pipeline/Palette.h), the same in every picture of every tool.
struct PlotSeries {
  std::string name;
  pipeline::Rgb colour;
  std::vector<double> x, y;
  PlotStyle style = PlotStyle::kLines;
};

/// An empty series named `name`, drawn in `colour` with `style`.
inline PlotSeries makeSeries(const std::string& name, pipeline::Rgb colour, PlotStyle style = PlotStyle::kLines) {
  return PlotSeries{name, colour, {}, {}, style};
}

/// Draws the series on equal-scale axes (trajectories, metres) with a legend, a grid and a
/// scale bar. Returns the PNG bytes.
std::string plotTrajectoriesPng(const std::vector<PlotSeries>& series, const std::string& title);

/// The histograms of positive samples (each series' x; y ignored) over `bins` logarithmic
/// bins spanning every series' samples: per series, x the bins' left edges (and the last
/// bin's right edge), y the share of the series' positive finite samples in each bin (0 at
/// the last edge), drawn as steps; name and colour kept. O(samples + bins) per series.
std::vector<PlotSeries> histogramShares(const std::vector<PlotSeries>& series, int bins);

/// Draws histograms of positive samples (e.g. times in microseconds) on a logarithmic x
/// axis, one per series (x holds the samples, y is ignored): histogramShares() with 60
/// bins. Returns the PNG bytes.
std::string plotHistogramsPng(const std::vector<PlotSeries>& series, const std::string& title,
                              const std::string& x_label);

/// Draws y against x (independent scales), lines or markers. `integer_x`: x takes whole
/// values (seeds, runs): ticks on whole numbers only, the points kept off the frame.
/// Returns the PNG bytes.
std::string plotXYPng(const std::vector<PlotSeries>& series, const std::string& title,
                      const std::string& x_label, const std::string& y_label, bool integer_x = false);

/// One scan's features, sensor frame (m): what scanFeaturesPng() draws.
struct ScanPicture {
  std::vector<std::pair<double, double>> points;  ///< valid beams' points
  std::vector<std::array<double, 4>> segments;    ///< x0, y0, x1, y1
  std::vector<std::pair<double, double>> doors;   ///< door centres
  std::vector<std::array<double, 4>> door_jambs;  ///< jamb_a x, y, jamb_b x, y
  std::vector<std::pair<double, double>> corners;
};
/// The paper's Fig. 6: the raw scan (left) beside its segments with doors as red circles
/// and corners as green circles (right); the robot is a red cross. Returns the PNG bytes.
std::string scanFeaturesPng(const ScanPicture& scan, const std::string& title);

}  // namespace lidarseg::apps
