// The charts' series (lidarseg/report/Plots.h): how a style is drawn, the histograms
// drawn as steps from their samples, and the paper's Fig. 6 drawn by gnuplot on equal scales.
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "EmptyPath.h"
#include "lidarseg/report/Plots.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::report {
namespace {

TEST(Plots, EachStyleHasItsGnuplotClause) {
  EXPECT_EQ(gnuplotWith(PlotStyle::kLines), "with lines lw 2");
  EXPECT_EQ(gnuplotWith(PlotStyle::kMarkers), "with points pt 7 ps 1.3");
  EXPECT_EQ(gnuplotWith(PlotStyle::kSteps), "with steps lw 2");
  EXPECT_EQ(makeSeries("a", kIcpColour).style, PlotStyle::kLines);
  EXPECT_EQ(makeSeries("a", kIcpColour, PlotStyle::kMarkers).style, PlotStyle::kMarkers);
}

// A series with no finite point (a reference outside the log's time span) does not stop the
// picture: gnuplot refused the whole plot for its empty data file. Nor does a plot where no
// series has a point: its frame says so.
TEST(Plots, ASeriesWithoutPointsStillGivesAPicture) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  PlotSeries mine = makeSeries("lidarseg", kLidarsegColour);
  mine.x = {0.0, 1.0, 2.0};
  mine.y = {0.0, 0.5, 0.0};
  PlotSeries none = makeSeries("ground truth", kIcpColour);
  none.x = {nan};
  none.y = {nan};
  for (const std::vector<PlotSeries>& series : {std::vector<PlotSeries>{mine, none}, std::vector<PlotSeries>{none}}) {
    for (const std::string& png : {plotTrajectoriesPng(series, "t"), plotXYPng(series, "t", "x", "y")}) {
      const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/empty_series.png";
      std::ofstream(path, std::ios::binary) << png;
      const auto header = vision::readImageHeader(path);
      ASSERT_TRUE(header.has_value()) << series.size();
      EXPECT_EQ(header->format, "PNG");
      EXPECT_GT(header->width, 100u);
    }
  }
}

TEST(Plots, HistogramsAreStepsOfEachSeriesSharesOverLogarithmicBins) {
  PlotSeries a = makeSeries("lidarseg", kLidarsegColour, PlotStyle::kMarkers);
  a.x = {1.0, 10.0, 100.0, 100.0, 0.0, -3.0, std::numeric_limits<double>::quiet_NaN()};  // 4 usable
  PlotSeries b = makeSeries("MRPT ICP keyframed", kIcpColour);
  b.x = {10.0};
  const std::vector<PlotSeries> h = histogramShares({a, b}, 4);
  ASSERT_EQ(h.size(), 2u);
  for (const PlotSeries& s : h) {
    EXPECT_EQ(s.style, PlotStyle::kSteps) << s.name;
    ASSERT_EQ(s.x.size(), 5u);
    ASSERT_EQ(s.y.size(), 5u);
    // Bin edges from the smallest to the largest sample of every series, 10^0.5 apart.
    for (std::size_t k = 0; k < s.x.size(); ++k) EXPECT_NEAR(s.x[k], std::pow(10.0, 0.5 * static_cast<double>(k)), 1e-9) << k;
    EXPECT_NEAR(std::accumulate(s.y.begin(), s.y.end(), 0.0), 1.0, 1e-12) << s.name;
    EXPECT_EQ(s.y.back(), 0.0);  // the last edge closes the last bin
  }
  EXPECT_EQ(h[0].name, "lidarseg");
  EXPECT_EQ(h[0].colour.b, kLidarsegColour.b);
  EXPECT_EQ(h[1].colour.r, kIcpColour.r);
  // 1 in the first bin, 10 in the third, both 100s in the last.
  EXPECT_DOUBLE_EQ(h[0].y[0], 0.25);
  EXPECT_DOUBLE_EQ(h[0].y[1], 0.0);
  EXPECT_DOUBLE_EQ(h[0].y[2], 0.25);
  EXPECT_DOUBLE_EQ(h[0].y[3], 0.5);
  EXPECT_DOUBLE_EQ(h[1].y[2], 1.0);
}

// A corridor 2.4 m wide along x seen from its middle: points on both walls every 5 cm to
// 12 m ahead, the two walls as segments, a door in the left wall and a corner ahead.
ScanPicture corridorScan() {
  ScanPicture scan;
  for (double x = -1.0; x <= 12.0; x += 0.05) scan.points.emplace_back(x, 1.2), scan.points.emplace_back(x, -1.2);
  scan.segments = {{-1.0, 1.2, 3.0, 1.2}, {4.0, 1.2, 12.0, 1.2}, {-1.0, -1.2, 12.0, -1.2}};
  scan.doors = {{3.5, 1.2}};
  scan.door_jambs = {{3.0, 1.2, 4.0, 1.2}};
  scan.corners = {{12.0, -1.2}};
  return scan;
}

// The picture's pixel of a point of the sensor frame in panel `panel`.
cv::Point pixelOf(const ScanFigureLayout& L, int panel, double x, double y) {
  const double scale = L.plot_width_px / (L.x_max_m - L.x_min_m);
  return {static_cast<int>(std::lround(L.plot_left_px[panel] + (x - L.x_min_m) * scale)),
          static_cast<int>(std::lround(L.plot_top_px + (L.y_max_m - y) * scale))};
}

// Whether a pixel within `radius` of `at` has `colour` (each channel within 40: the lines
// are anti-aliased).
bool hasColourNear(const cv::Mat& bgr, cv::Point at, int radius, Rgb colour) {
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const cv::Point p = at + cv::Point(dx, dy);
      if (p.x < 0 || p.y < 0 || p.x >= bgr.cols || p.y >= bgr.rows) continue;
      const cv::Vec3b c = bgr.at<cv::Vec3b>(p);
      if (std::abs(c[2] - colour.r) <= 40 && std::abs(c[1] - colour.g) <= 40 && std::abs(c[0] - colour.b) <= 40) {
        return true;
      }
    }
  }
  return false;
}

TEST(Plots, TheScanFigureFitsEverythingOnEqualScales) {
  const ScanPicture scan = corridorScan();
  const ScanFigureLayout L = scanFigureLayout(scan);
  EXPECT_EQ(L.width_px, 1600);
  // A metre as long on x as on y, and both panels the same.
  EXPECT_NEAR((L.x_max_m - L.x_min_m) / L.plot_width_px, (L.y_max_m - L.y_min_m) / L.plot_height_px, 1e-9);
  EXPECT_EQ(L.plot_left_px[1] - L.plot_left_px[0], L.width_px / 2);
  EXPECT_LE(L.plot_left_px[1] + L.plot_width_px, L.width_px);
  EXPECT_LE(L.plot_top_px + L.plot_height_px, L.height_px);
  EXPECT_GE(L.plot_height_px, 300);
  EXPECT_LE(L.plot_height_px, 1000);
  // Every point and the sensor inside, 13 m of corridor across.
  for (const auto& [x, y] : scan.points) {
    EXPECT_TRUE(x > L.x_min_m && x < L.x_max_m && y > L.y_min_m && y < L.y_max_m) << x << " " << y;
  }
  EXPECT_LT(L.x_min_m, -1.0);
  EXPECT_GT(L.x_max_m, 12.0);
  EXPECT_LT(L.x_max_m - L.x_min_m, 16.0);
  EXPECT_DOUBLE_EQ(L.scale_bar_m, 2.0);  // 1/6 of about 14 m, rounded down to 1, 2 or 5
  // A corridor along y is as tall as a panel may be, and still on equal scales.
  ScanPicture tall;
  for (const auto& [x, y] : scan.points) tall.points.emplace_back(y, x);
  const ScanFigureLayout T = scanFigureLayout(tall);
  EXPECT_EQ(T.plot_height_px, 1000);
  EXPECT_NEAR((T.x_max_m - T.x_min_m) / T.plot_width_px, (T.y_max_m - T.y_min_m) / T.plot_height_px, 1e-9);
  EXPECT_GT(T.y_max_m, 12.0);
  EXPECT_LT(T.y_min_m, -1.0);
}

TEST(Plots, TheScanFigureIsAPngOfItsLayoutWithThePalettesColoursInPlace) {
  const ScanPicture scan = corridorScan();
  const ScanFigureLayout L = scanFigureLayout(scan);
  const std::string path = std::string(LIDARSEG_TEST_TMP_DIR) + "/scan_figure.png";
  std::ofstream(path, std::ios::binary) << scanFeaturesPng(scan, "a corridor");
  const auto header = vision::readImageHeader(path);
  ASSERT_TRUE(header.has_value());
  EXPECT_EQ(header->format, "PNG");
  EXPECT_EQ(header->width, static_cast<std::uint64_t>(L.width_px));
  EXPECT_EQ(header->height, static_cast<std::uint64_t>(L.height_px));
  // Each mark where the layout puts it: the sensor in both panels, the raw points left, the
  // segments, the door and the corner right; none of the right panel's marks on the left.
  const cv::Mat img = vision::readImage(path);
  for (int panel = 0; panel < 2; ++panel) {
    EXPECT_TRUE(hasColourNear(img, pixelOf(L, panel, 0, 0), 3, kRobotColour)) << panel;
  }
  EXPECT_TRUE(hasColourNear(img, pixelOf(L, 0, 8.0, -1.2), 3, kScanPointColour));
  EXPECT_TRUE(hasColourNear(img, pixelOf(L, 1, 8.0, -1.2), 2, kLidarsegColour));
  EXPECT_FALSE(hasColourNear(img, pixelOf(L, 0, 8.0, -1.2), 3, kLidarsegColour));
  // A circle is drawn around its centre: look on its ring, at about its radius.
  const auto ring = [&](int panel, double x, double y, Rgb c) {
    for (int r = 6; r <= 16; ++r) {
      if (hasColourNear(img, pixelOf(L, panel, x, y) + cv::Point(r, 0), 0, c)) return true;
    }
    return false;
  };
  EXPECT_TRUE(ring(1, 3.5, 1.2, kDoorColour));
  EXPECT_TRUE(ring(1, 12.0, -1.2, kCornerColour));
  EXPECT_FALSE(ring(0, 12.0, -1.2, kCornerColour));
  // An empty scan still draws: the sensor alone, 2 m across at least.
  const ScanFigureLayout E = scanFigureLayout(ScanPicture{});
  EXPECT_GE(E.x_max_m - E.x_min_m, 2.0);
  std::ofstream(path, std::ios::binary) << scanFeaturesPng(ScanPicture{}, "nothing");
  EXPECT_EQ(vision::readImageHeader(path)->height, static_cast<std::uint64_t>(E.height_px));
}

TEST(Plots, WithoutGnuplotTheScanFigureIsRefusedNamingIt) {
  std::string what;
  {
    const lidarseg::testing::EmptyPath no_gnuplot;
    try {
      scanFeaturesPng(corridorScan(), "a corridor");
    } catch (const std::runtime_error& e) {
      what = e.what();
    }
  }
  EXPECT_NE(what.find("gnuplot is not installed"), std::string::npos) << what;
}

}  // namespace
}  // namespace lidarseg::report
