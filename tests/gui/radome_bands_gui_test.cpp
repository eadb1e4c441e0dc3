// Radome's innovation plot draws three overlapping ± 2√S bands: each is named in the legend and
// told apart where they overlap by its edges, drawn opaque in the band's colour and its own dash;
// in the rendered plot each band's edge shows in its colour.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QImage>
#include <cmath>
#include <set>
#include <utility>

#include "common/plot_probe.h"
#include "main_window.h"
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
  QCustomPlot* p = testing::plotNamed(w, "innovation");
  ASSERT_NE(p, nullptr);
  QList<const QCPGraph*> uppers;
  for (int i = 0; i < p->graphCount(); ++i) {
    const QCPGraph* g = p->graph(i);
    if (g->channelFillGraph()) uppers << g->channelFillGraph();
  }
  ASSERT_EQ(uppers.size(), 3);
  std::set<std::pair<QRgb, int>> looks;
  for (const QCPGraph* u : uppers) {
    EXPECT_FALSE(u->name().isEmpty());
    EXPECT_TRUE(p->legend->hasItemWithPlottable(u)) << u->name().toStdString();
    EXPECT_EQ(u->pen().color().alpha(), 255) << u->name().toStdString() << ": edge not opaque";
    EXPECT_GE(u->pen().widthF(), 1.5);
    looks.insert({u->pen().color().rgb(), static_cast<int>(u->pen().style())});
  }
  EXPECT_EQ(looks.size(), 3u) << "two bands share colour and dash";
  std::set<int> styles;
  for (const QCPGraph* u : uppers)
    styles.insert(static_cast<int>(u->pen().style()));
  EXPECT_EQ(styles.size(), 3u) << "each band its own dash (colour-blind readers)";

  // Rendered: along each band's upper edge, pixels nearest its own colour (not a blend).
  const QImage img = p->toPixmap(p->width(), p->height(), 1.0).toImage();
  const QRect rect = p->axisRect()->rect();
  for (const QCPGraph* u : uppers) {
    const QColor mine = u->pen().color();
    int columns = 0, hits = 0;
    for (int x = rect.left() + 10; x < rect.right() - 10; x += 7) {
      const double t = p->xAxis->pixelToCoord(x);
      const double v = plot::valueAt(u, t);
      if (!std::isfinite(v)) continue;
      const int y = static_cast<int>(std::lround(p->yAxis->coordToPixel(v)));
      if (y < rect.top() + 2 || y > rect.bottom() - 2) continue;
      ++columns;
      bool hit = false;
      for (int dx = 0; dx < 7 && !hit; ++dx) {
        for (int dy = -1; dy <= 1 && !hit; ++dy) {
          const QColor c = img.pixelColor(x + dx, y + dy);
          bool nearest = distance(c, mine) < 120;
          for (const QCPGraph* o : uppers) {
            if (o != u && distance(c, o->pen().color()) <= distance(c, mine)) nearest = false;
          }
          hit = nearest;
        }
      }
      hits += hit;
    }
    ASSERT_GT(columns, 20) << u->name().toStdString();
    EXPECT_GE(hits, columns * 6 / 10) << u->name().toStdString() << ": " << hits << " of "
                                      << columns << " columns show the edge in its colour";
  }
}

}  // namespace
}  // namespace kfw
