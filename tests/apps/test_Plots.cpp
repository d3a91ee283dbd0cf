// The charts' series (libs/apps' private Plots.h): how a style is drawn, and the histograms
// drawn as steps from their samples.
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "Plots.h"

namespace lidarseg::apps {
namespace {

TEST(Plots, EachStyleHasItsGnuplotClause) {
  EXPECT_EQ(gnuplotWith(PlotStyle::kLines), "with lines lw 2");
  EXPECT_EQ(gnuplotWith(PlotStyle::kMarkers), "with points pt 7 ps 1.3");
  EXPECT_EQ(gnuplotWith(PlotStyle::kSteps), "with steps lw 2");
  EXPECT_EQ(makeSeries("a", pipeline::kIcpColour).style, PlotStyle::kLines);
  EXPECT_EQ(makeSeries("a", pipeline::kIcpColour, PlotStyle::kMarkers).style, PlotStyle::kMarkers);
}

TEST(Plots, HistogramsAreStepsOfEachSeriesSharesOverLogarithmicBins) {
  PlotSeries a = makeSeries("lidarseg", pipeline::kLidarsegColour, PlotStyle::kMarkers);
  a.x = {1.0, 10.0, 100.0, 100.0, 0.0, -3.0, std::numeric_limits<double>::quiet_NaN()};  // 4 usable
  PlotSeries b = makeSeries("MRPT ICP keyframed", pipeline::kIcpColour);
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
  EXPECT_EQ(h[0].colour.b, pipeline::kLidarsegColour.b);
  EXPECT_EQ(h[1].colour.r, pipeline::kIcpColour.r);
  // 1 in the first bin, 10 in the third, both 100s in the last.
  EXPECT_DOUBLE_EQ(h[0].y[0], 0.25);
  EXPECT_DOUBLE_EQ(h[0].y[1], 0.0);
  EXPECT_DOUBLE_EQ(h[0].y[2], 0.25);
  EXPECT_DOUBLE_EQ(h[0].y[3], 0.5);
  EXPECT_DOUBLE_EQ(h[1].y[2], 1.0);
}

}  // namespace
}  // namespace lidarseg::apps
