// Redrawing on two cores (draw_batch.h) gives the graphs the data an immediate redraw gives them,
// and the screen's fast band fill and dot raster (plot_fast.h) paint the picture QCustomPlot's
// own polygon and scatter drawing paint (the export path).
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QImage>
#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "draw_batch.h"
#include "plot_kit.h"

namespace kfw {
namespace {

struct Samples {
  std::vector<double> t, x, var, y;
};

Samples noisyRun(std::size_t n, unsigned seed) {
  Samples r;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 0.005 * static_cast<double>(i);
    r.t.push_back(t);
    r.x.push_back(std::sin(0.3 * t) + 0.2 * noise(rng));
    r.var.push_back(0.01 + 0.05 * std::exp(-t / 20.0) + 0.01 * std::abs(noise(rng)));
    r.y.push_back(noise(rng) * (1.0 + 0.5 * std::sin(0.1 * t)));
  }
  return r;
}

// A plot as the workbench makes it (the screen's look: no antialiasing of data and fills).
std::unique_ptr<QCustomPlot> newPlot() {
  std::unique_ptr<QCustomPlot> p(plot::makePlot(nullptr, "test", "time (s)", "x"));
  p->resize(900, 500);
  return p;
}

struct Plot {
  std::unique_ptr<QCustomPlot> owner = newPlot();
  QCustomPlot& p = *owner;
  plot::Band band, bare;
  QCPGraph *line, *dots;
  QCPCurve* curve;
  Plot() {
    band = plot::addBand(&p, "band", plot::color::kEstimate);
    bare = plot::addBand(&p, "bare", plot::color::kSecond);
    line = plot::addGraph(&p, "line", plot::color::kEstimate);
    dots = plot::addGraph(&p, "dots", plot::color::kSensor, plot::Style::kDots);
    curve = new QCPCurve(p.xAxis, p.yAxis);
    p.replot();  // laid out, as a window's plots are before their first run
  }
  void draw(const Samples& r) {
    plot::setSigmaBand(band, r.t, &r.x, r.var, 2.0, plot::kAll);
    plot::setSigmaBand(bare, r.t, nullptr, r.var, 2.0, plot::kAll);
    plot::setSeries(line, r.t, r.x, plot::kAll);
    plot::setSeries(dots, r.t, r.y, plot::kAll);
    plot::setCurve(curve, r.x, r.y, plot::kAll);
    plot::rescale(&p, r.t.front(), r.t.back());
    plot::replot(&p);
  }
};

std::vector<std::pair<double, double>> points(const QCPGraph* g) {
  std::vector<std::pair<double, double>> out;
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it)
    out.emplace_back(it->key, it->value);
  return out;
}

std::vector<std::pair<double, double>> points(const QCPCurve* c) {
  std::vector<std::pair<double, double>> out;
  for (auto it = c->data()->constBegin(); it != c->data()->constEnd(); ++it)
    out.emplace_back(it->key, it->value);
  return out;
}

TEST(DrawBatch, GivesTheGraphsWhatAnImmediateRedrawGives) {
  const Samples first = noisyRun(60000, 1), second = noisyRun(60000, 2);
  Plot now, batched;
  now.draw(first);
  now.draw(second);
  {
    plot::DrawBatch batch;
    // Two redraws in one batch (a run, then a cursor move): the later one's data win.
    batched.draw(first);
    batched.draw(second);
    // Inside the batch the axes were fitted to the data (rescale waited for the reductions).
    EXPECT_EQ(batched.p.yAxis->range(), now.p.yAxis->range());
  }
  EXPECT_GT(now.line->data()->size(), 100);
  for (auto [a, b] : {std::pair{now.line, batched.line},
                      {now.dots, batched.dots},
                      {now.band.upper, batched.band.upper},
                      {now.band.lower, batched.band.lower},
                      {now.bare.upper, batched.bare.upper},
                      {now.bare.lower, batched.bare.lower}})
    EXPECT_EQ(points(a), points(b)) << a->name().toStdString();
  EXPECT_EQ(points(now.curve), points(batched.curve));
  // The readout's exact values come from the same source arrays.
  EXPECT_EQ(plot::seriesSource(batched.line).y, &second.x);
}

TEST(DrawBatch, CentrelessSigmaBandIsPlusMinusTheColumnsLargestSigma) {
  const Samples r = noisyRun(60000, 3);
  Plot p;
  p.draw(r);
  const auto up = points(p.bare.upper), lo = points(p.bare.lower);
  ASSERT_EQ(up.size(), lo.size());
  ASSERT_GT(up.size(), 100u);
  double largest = 0.0;
  for (double v : r.var)
    largest = std::max(largest, 2.0 * std::sqrt(v));
  double top = 0.0;
  for (std::size_t i = 0; i < up.size(); ++i) {
    EXPECT_DOUBLE_EQ(lo[i].second, -up[i].second);
    top = std::max(top, up[i].second);
  }
  EXPECT_DOUBLE_EQ(top, largest);
}

// The plot as the screen draws it (replot + paint) and as an export draws it (toPixmap).
QImage screen(QCustomPlot& p) {
  p.replot();
  QImage img = p.grab().toImage().convertToFormat(QImage::Format_RGB32);
  if (qEnvironmentVariableIsSet("KFW_TEST_SAVE")) img.save("/tmp/shots/screen.png");
  return img;
}
QImage exported(QCustomPlot& p) {
  QImage img = p.toPixmap(p.width(), p.height()).toImage().convertToFormat(QImage::Format_RGB32);
  if (qEnvironmentVariableIsSet("KFW_TEST_SAVE")) img.save("/tmp/shots/exported.png");
  return img;
}

std::set<std::pair<int, int>> pixelsOf(const QImage& img, QRgb c, const QRect& area) {
  std::set<std::pair<int, int>> out;
  for (int y = area.top(); y <= area.bottom(); ++y) {
    for (int x = area.left(); x <= area.right(); ++x) {
      if ((img.pixel(x, y) & 0xffffff) == (c & 0xffffff)) out.emplace(x, y);
    }
  }
  return out;
}

TEST(FastDraw, BandFillCoversThePolygonsPixels) {
  const Samples r = noisyRun(60000, 4);
  auto owner = newPlot();
  QCustomPlot& p = *owner;
  plot::Band b = plot::addBand(&p, "band", plot::color::kEstimate);
  plot::setSigmaBand(b, r.t, &r.x, r.var, 2.0, plot::kAll);
  plot::rescale(&p, r.t.front(), r.t.back());
  const QRgb fill = b.lower->brush().color().rgb();
  const QImage fast_img = screen(p);
  const QRect area = p.axisRect()->rect().adjusted(2, 2, -2, -2);
  const auto fast = pixelsOf(fast_img, fill, area);
  const auto poly = pixelsOf(exported(p), fill, area);
  ASSERT_GT(poly.size(), 5000u);
  // The same area to within the edge lines' pixels (the envelope of each column pair).
  std::size_t only_fast = 0, only_poly = 0;
  for (const auto& px : fast)
    only_fast += poly.count(px) ? 0 : 1;
  for (const auto& px : poly)
    only_poly += fast.count(px) ? 0 : 1;
  EXPECT_LT(static_cast<double>(only_fast + only_poly), 0.03 * static_cast<double>(poly.size()))
      << only_fast << " only in the fast fill, " << only_poly << " only in the polygon, of "
      << poly.size();
}

TEST(FastDraw, DotRasterPaintsEveryDotQCustomPlotPaintsAndNothingElse) {
  const Samples r = noisyRun(60000, 5);
  auto owner = newPlot();
  QCustomPlot& p = *owner;
  QCPGraph* g = plot::addGraph(&p, "dots", QColor(200, 30, 30), plot::Style::kDots);
  plot::setSeries(g, r.t, r.y, plot::kAll);
  plot::rescale(&p, r.t.front(), r.t.back());
  const QRgb c = QColor(200, 30, 30).rgb();
  const QImage fast_img = screen(p);
  const QRect area = p.axisRect()->rect();
  const auto fast = pixelsOf(fast_img, c, area);
  const auto qcp = pixelsOf(exported(p), c, area);  // still pixmap dots: the screen look
  ASSERT_GT(qcp.size(), 1000u);
  for (const auto& px : qcp)
    EXPECT_TRUE(fast.count(px)) << "QCustomPlot's dot pixel " << px.first << "," << px.second;
  // Each painted pixel belongs to the 2 × 2 square of a point of the graph.
  std::set<std::pair<int, int>> expected;
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it) {
    // (QCustomPlot's antialiased scatters sit half a pixel on: one pixel right and down)
    const long x0 = std::lround(p.xAxis->coordToPixel(it->key) - 1.0) + 1;
    const long y0 = std::lround(p.yAxis->coordToPixel(it->value) - 1.0) + 1;
    for (long y = y0; y < y0 + 2; ++y) {
      for (long x = x0; x < x0 + 2; ++x)
        expected.emplace(static_cast<int>(x), static_cast<int>(y));
    }
  }
  for (const auto& px : fast)
    EXPECT_TRUE(expected.count(px)) << "a stray pixel at " << px.first << "," << px.second;
}

}  // namespace
}  // namespace kfw
