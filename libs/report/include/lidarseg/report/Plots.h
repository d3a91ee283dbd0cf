#pragma once
/// @file
/// lidarseg::report: the charts of every tool's report - the pictures of a run
/// (trajectories, timing histograms, per-run errors) and a scan's features (the paper's
/// Fig. 6) as PNG images drawn by gnuplot (pngcairo), one colour per method from Palette.h.
/// The drawing functions throw std::runtime_error when gnuplot is missing (PlotterMissing)
/// or fails (with what gnuplot said, or how it ended: never an empty reason).

#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lidarseg/core/Feature.h"
#include "lidarseg/core/Segmentation.h"
#include "lidarseg/report/Palette.h"

namespace lidarseg::report {

/// gnuplot is not installed: a tool writes no picture and warns (decision 55).
class PlotterMissing : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a series is drawn.
enum class PlotStyle {
  kLines,    ///< a polyline through the points
  kMarkers,  ///< a dot at each point
  kSteps,    ///< steps: each y held from its x to the next x (histograms' bins)
};

/// gnuplot's `with` clause of a style, e.g. "with steps lw 2".
std::string gnuplotWith(PlotStyle style);

/// A named series of points (x, y) drawn in one colour: one of the palette's
/// (lidarseg/report/Palette.h), the same in every picture of every tool.
struct PlotSeries {
  std::string name;
  Rgb colour;
  std::vector<double> x, y;
  PlotStyle style = PlotStyle::kLines;
};

/// An empty series named `name`, drawn in `colour` with `style`.
inline PlotSeries makeSeries(const std::string& name, Rgb colour, PlotStyle style = PlotStyle::kLines) {
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

/// One scan as the paper's Fig. 6 draws it: the valid beams' points, the segments of
/// `level`, the doors (centres and jambs) and corners (sensor frame). O(points + segments +
/// features).
ScanPicture scanPictureOf(const Segmentation& segmentation, CascadeLevel level, const std::vector<Feature>& features);

/// Where scanFeaturesPng() draws: the picture's size and each panel's view, one scale
/// (pixels per metre) on both axes of both panels.
struct ScanFigureLayout {
  int width_px = 0, height_px = 0;  ///< the PNG's size
  /// Each panel's plot (inside its frame), pixels from the picture's left and top: the left
  /// edges of the raw scan's and the segments' panels, the top edge, the width and height.
  int plot_left_px[2] = {0, 0};
  int plot_top_px = 0, plot_width_px = 0, plot_height_px = 0;
  double x_min_m = 0, x_max_m = 0;  ///< each panel's x range (sensor frame)
  double y_min_m = 0, y_max_m = 0;  ///< each panel's y range (sensor frame)
  double scale_bar_m = 1;           ///< the scale bar's length: 1, 2 or 5 times a power of ten
};

/// The layout of scanFeaturesPng() for `scan`: 1600 pixels wide, two panels side by side,
/// each fitting every point, segment end, feature and the sensor with a margin (at least
/// 2 m across), a band above the data for the legend and one below for the scale bar; the
/// height follows the data's aspect (each panel's plot 300 to 1000 pixels high) and the
/// ranges are widened so that a metre is as long on x as on y. O(size of `scan`).
ScanFigureLayout scanFigureLayout(const ScanPicture& scan);

/// The paper's Fig. 6 drawn by gnuplot (pngcairo), laid out by scanFigureLayout(): the raw
/// scan (left) beside its segments (right) with doors as red circles and their jambs
/// joined in red, corners as green circles, the sensor as a red cross in both; axes in
/// metres on equal scales, a legend inside each frame, a scale bar; colours from
/// lidarseg/report/Palette.h. Returns the PNG bytes.
/// @throws std::runtime_error when gnuplot is missing or fails.
std::string scanFeaturesPng(const ScanPicture& scan, const std::string& title);

}  // namespace lidarseg::report
