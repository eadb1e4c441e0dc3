// Radome's innovations with their ± 2√S bands: the built-in drew the three components' bands in
// one plot, overlapping, each told apart by its colour and dash. Since issue 28 the preset is seed
// 001's model file and the generic view draws each component in its own plot
// (innovation.seeker.Yx, .Yy, .Yz), so no two bands overlap; each is named in the legend and
// rendered in its colour under the innovation.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "plot_kit.h"
#include "plot_readout.h"

namespace kfw {
namespace {

int distance(const QColor& a, const QColor& b) {
  return std::abs(a.red() - b.red()) + std::abs(a.green() - b.green()) +
         std::abs(a.blue() - b.blue());
}

TEST(RadomeBands, EveryBandNamedAndDistinguishableWhereTheyOverlap) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("radome").ok());
  w.resize(1600, 1000);
  w.show();
  ASSERT_TRUE(w.waitForRun(60000));
  for (const char* name :
       {"innovation.seeker.Yx", "innovation.seeker.Yy", "innovation.seeker.Yz"}) {
    SCOPED_TRACE(name);
    QCustomPlot* p = testing::plotNamed(w, name);
    ASSERT_NE(p, nullptr);
    QList<const QCPGraph*> lowers;
    for (int i = 0; i < p->graphCount(); ++i) {
      if (p->graph(i)->channelFillGraph()) lowers << p->graph(i);
    }
    ASSERT_EQ(lowers.size(), 1);  // one band a plot: nothing overlaps
    const QCPGraph* lower = lowers.front();
    const QCPGraph* upper = lower->channelFillGraph();
    const QCPGraph* named = p->legend->hasItemWithPlottable(lower) ? lower : upper;
    EXPECT_FALSE(named->name().isEmpty());
    EXPECT_TRUE(p->legend->hasItemWithPlottable(named));
    // Rendered: between the band's edges, where it is a few pixels wide, its fill's colour.
    p->replot();
    const QImage img = p->toPixmap(p->width(), p->height(), 1.0).toImage();
    const QRect rect = p->axisRect()->rect();
    const QColor fill = lower->brush().color();
    int columns = 0, hits = 0;
    for (int x = rect.left() + 10; x < rect.right() - 10; x += 7) {
      const double t = p->xAxis->pixelToCoord(x);
      const double lo = plot::valueAt(lower, t), hi = plot::valueAt(upper, t);
      if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
      const double ylo = p->yAxis->coordToPixel(lo), yhi = p->yAxis->coordToPixel(hi);
      if (std::fabs(ylo - yhi) < 8 || std::min(ylo, yhi) < rect.top() ||
          std::max(ylo, yhi) > rect.bottom())
        continue;
      ++columns;
      // A quarter of the way in from an edge: away from the innovation line in the middle.
      const int y = static_cast<int>(std::lround(0.75 * ylo + 0.25 * yhi));
      hits += distance(img.pixelColor(x, y), fill) < 60;
    }
    ASSERT_GT(columns, 20);
    EXPECT_GE(hits, columns * 6 / 10) << hits << " of " << columns << " columns";
  }
}

}  // namespace
}  // namespace kfw
