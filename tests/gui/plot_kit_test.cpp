// plot_kit's decimation keeps what a raster can show: extremes, ends, and every occupied cell.
#include "plot_kit.h"

#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace kfw {
namespace {

struct Series {
  std::vector<double> x, y;
};

Series noisySine(std::size_t n) {
  Series s;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.3);
  for (std::size_t i = 0; i < n; ++i) {
    s.x.push_back(0.01 * static_cast<double>(i));
    s.y.push_back(std::sin(0.002 * static_cast<double>(i)) + noise(rng));
  }
  return s;
}

TEST(PlotKit, DenseLineKeepsEndsAndExtremes) {
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "line", Qt::blue);
  const auto s = noisySine(100000);
  plot::setSeries(g, s.x, s.y, plot::kAll);
  EXPECT_LT(g->data()->size(), 10000);
  EXPECT_DOUBLE_EQ(g->data()->constBegin()->key, s.x.front());
  EXPECT_DOUBLE_EQ((g->data()->constEnd() - 1)->key, s.x.back());
  bool found = false;
  const auto range = g->data()->valueRange(found);
  EXPECT_DOUBLE_EQ(range.lower, *std::min_element(s.y.begin(), s.y.end()));
  EXPECT_DOUBLE_EQ(range.upper, *std::max_element(s.y.begin(), s.y.end()));
}

TEST(PlotKit, SparseSeriesAndPrefixAreExact) {
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "line", Qt::blue);
  auto s = noisySine(3000);
  s.y[10] = std::nan("");
  plot::setSeries(g, s.x, s.y, 500);
  EXPECT_EQ(g->data()->size(), 499);  // 500 revealed, one NaN dropped
  plot::setSeries(g, s.x, s.y, 500, false);
  EXPECT_EQ(g->data()->size(), 500);  // the NaN kept as a gap
}

TEST(PlotKit, DenseBandIsTheColumnEnvelope) {
  QCustomPlot p;
  const auto band = plot::addBand(&p, "band", Qt::blue);
  const auto s = noisySine(100000);
  std::vector<double> half(s.y.size(), 0.5);
  plot::setBand(band, s.x, s.y, half, plot::kAll);
  bool found = false;
  EXPECT_DOUBLE_EQ(band.upper->data()->valueRange(found).upper,
                   *std::max_element(s.y.begin(), s.y.end()) + 0.5);
  EXPECT_DOUBLE_EQ(band.lower->data()->valueRange(found).lower,
                   *std::min_element(s.y.begin(), s.y.end()) - 0.5);
  EXPECT_EQ(band.upper->data()->size(), band.lower->data()->size());
  EXPECT_LT(band.upper->data()->size(), 5000);
}

TEST(PlotKit, DenseDotsKeepOneDotPerCell) {
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "dots", Qt::blue, plot::Style::kDots);
  const auto s = noisySine(200000);
  plot::setSeries(g, s.x, s.y, plot::kAll);
  EXPECT_LT(g->data()->size(), 200000);
  EXPECT_GT(g->data()->size(), 5000);
  bool found = false;
  const auto range = g->data()->valueRange(found);
  EXPECT_DOUBLE_EQ(range.lower, *std::min_element(s.y.begin(), s.y.end()));
  EXPECT_DOUBLE_EQ(range.upper, *std::max_element(s.y.begin(), s.y.end()));
}

}  // namespace
}  // namespace kfw
