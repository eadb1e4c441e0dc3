// plot_kit's decimation keeps what a raster can show: extremes, ends, and every occupied cell.
#include "plot_kit.h"

#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

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

TEST(PlotKit, DenseStepGraphKeepsItsLevelsAndEnds) {
  // A gain held between updates (NaN between them): reduced like a line, every level reached in
  // the data is still drawn, and the last level holds to the end.
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "gain", Qt::blue, plot::Style::kStep);
  std::vector<double> x, y;
  for (int i = 0; i < 60000; ++i) {
    x.push_back(0.01 * i);
    y.push_back(i % 3 == 0 ? 0.5 + 0.4 * std::exp(-0.001 * i) : std::nan(""));
  }
  plot::setSeries(g, x, y, plot::kAll);
  EXPECT_LT(g->data()->size(), 5000);
  bool found = false;
  const auto range = g->data()->valueRange(found);
  EXPECT_DOUBLE_EQ(range.upper, 0.9);
  EXPECT_DOUBLE_EQ(range.lower, y[59997]);
  EXPECT_DOUBLE_EQ((g->data()->constEnd() - 1)->key, x[59997]);
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

TEST(PlotKit, DotsOnALogAxisKeepTheDecades) {
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "dots", Qt::blue, plot::Style::kDots);
  plot::setLog(p.yAxis);
  std::vector<double> x, y;
  std::mt19937 rng(5);
  std::chi_squared_distribution<double> chi2(1.0);
  for (int i = 0; i < 100000; ++i) {
    x.push_back(0.001 * i);
    y.push_back(i % 7 == 0 ? -1.0
                           : chi2(rng));  // non-positive values cannot be drawn on a log axis
  }
  plot::setSeries(g, x, y, plot::kAll);
  EXPECT_LT(g->data()->size(), 50000);
  double lo = 1e300, hi = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (y[i] > 0) lo = std::min(lo, y[i]), hi = std::max(hi, y[i]);
  }
  bool found = false;
  const auto range = g->data()->valueRange(found);
  EXPECT_DOUBLE_EQ(range.lower, lo);
  EXPECT_DOUBLE_EQ(range.upper, hi);
}

TEST(PlotKit, UnsortedDotsComeOutSortedWithEveryRow) {
  QCustomPlot p;
  QCPGraph* g = plot::addGraph(&p, "raster", Qt::blue, plot::Style::kDots);
  std::vector<double> t, row;
  for (int r = 0; r < 5; ++r) {
    for (int k = 0; k < 20000; ++k) {
      t.push_back(0.01 * k);
      row.push_back(r);
    }
  }
  plot::setDots(g, t, row);
  EXPECT_LT(g->data()->size(), 20000);
  std::set<double> rows;
  double last = -1;
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it) {
    EXPECT_GE(it->key, last);
    last = it->key;
    rows.insert(it->value);
  }
  EXPECT_EQ(rows.size(), 5U);
}

TEST(PlotKit, DenseCurveKeepsItsEndsAndShape) {
  QCustomPlot p;
  auto* c = new QCPCurve(p.xAxis, p.yAxis);
  std::vector<double> east, north;
  for (int i = 0; i <= 40000; ++i) {
    const double a = 1e-4 * i;  // two thirds of a turn, 40 001 points
    east.push_back(std::cos(a));
    north.push_back(std::sin(a));
  }
  plot::setCurve(c, east, north, plot::kAll);
  EXPECT_LT(c->data()->size(), 20000);
  EXPECT_GT(c->data()->size(), 1000);
  EXPECT_DOUBLE_EQ(c->data()->constBegin()->key, east.front());
  EXPECT_DOUBLE_EQ((c->data()->constEnd() - 1)->key, east.back());
  EXPECT_DOUBLE_EQ((c->data()->constEnd() - 1)->value, north.back());
  // Every kept point lies on the circle, and no two neighbours are far apart.
  auto prev = c->data()->constBegin();
  for (auto it = c->data()->constBegin(); it != c->data()->constEnd(); prev = it++) {
    EXPECT_NEAR(std::hypot(it->key, it->value), 1.0, 1e-12);
    EXPECT_LT(std::hypot(it->key - prev->key, it->value - prev->value), 0.01);
  }
}

TEST(PlotKit, ExportLookDrawsVectorDotsAndLeavesMarkersAlone) {
  QCustomPlot p;
  QCPGraph* dots = plot::addGraph(&p, "dots", Qt::blue, plot::Style::kDots);
  QCPGraph* marks = plot::addGraph(&p, "marks", Qt::red, plot::Style::kDots);
  marks->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCross, 6));
  EXPECT_EQ(dots->scatterStyle().shape(), QCPScatterStyle::ssPixmap);
  plot::setExportLook(&p, true);
  EXPECT_EQ(dots->scatterStyle().shape(), QCPScatterStyle::ssSquare);
  EXPECT_EQ(marks->scatterStyle().shape(), QCPScatterStyle::ssCross);
  EXPECT_EQ(p.notAntialiasedElements(), QCP::aeNone);
  plot::setExportLook(&p, false);
  EXPECT_EQ(dots->scatterStyle().shape(), QCPScatterStyle::ssPixmap);
  EXPECT_EQ(marks->scatterStyle().shape(), QCPScatterStyle::ssCross);
  EXPECT_TRUE(p.notAntialiasedElements().testFlag(QCP::aePlottables));
}

// A plot never drawn in the window (out of view, draw_batch.h) was exported with its legend in
// one row: fifteen gain entries cut to "K[x, r". fitLegend wraps at any width it is given.
TEST(PlotKit, LegendWrapsToTheWidthItIsGiven) {
  QCustomPlot* p = plot::makePlot(nullptr, "gains", "time (s)", "gain (-)");
  for (int i = 0; i < 15; ++i)
    plot::addGraph(p, QString("K[x, range%1] (-)").arg(i), plot::color::cycle(i));
  EXPECT_EQ(p->legend->wrap(), 0);  // never replotted: one row
  int widest = 0;
  for (int i = 0; i < p->legend->itemCount(); ++i)
    widest = std::max(widest, p->legend->item(i)->minimumOuterSizeHint().width());
  for (int width : {1200, 500}) {
    plot::fitLegend(p, width);
    const int cols = p->legend->wrap();
    EXPECT_GE(cols, 1) << width;
    EXPECT_LE(cols * widest, width) << width;  // every entry whole
    EXPECT_GT((cols + 1) * (widest + p->legend->columnSpacing()), width - 16) << width;
  }
  delete p;
}

}  // namespace
}  // namespace kfw
