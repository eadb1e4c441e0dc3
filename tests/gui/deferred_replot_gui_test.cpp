// Issue 27, the underwater file's latency: a plot that is not on screen (scrolled out of the plot
// area, on another tab) is not drawn when a run asks for it, but before it is next painted
// (widgets/draw_batch.cpp); a plot in view is drawn at once.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QApplication>
#include <QScrollArea>

#include "common/plot_probe.h"
#include "main_window.h"

namespace kfw {
namespace {

using testing::plotNamed;

TEST(DeferredReplot, OnlyPlotsInViewDrawAfterARunTheRestWhenShown) {
  MainWindow w;
  w.resize(1280, 720);
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/underwater.json").ok());
  w.show();
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  QCustomPlot* top = plotNamed(w, "state.x");       // first in the plot area
  QCustomPlot* below = plotNamed(w, "covariance");  // last: scrolled out of view
  ASSERT_TRUE(top && below);
  ASSERT_FALSE(top->visibleRegion().isEmpty());
  ASSERT_TRUE(below->visibleRegion().isEmpty());
  int top_draws = 0, below_draws = 0;
  QObject::connect(top, &QCustomPlot::afterReplot, [&] { ++top_draws; });
  QObject::connect(below, &QCustomPlot::afterReplot, [&] { ++below_draws; });

  w.setParam("q_pos", 0.2);
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  EXPECT_GE(top_draws, 1);
  EXPECT_EQ(below_draws, 0);

  // Scrolled into view: drawn before it is painted, with the new run's numbers.
  auto* area = qobject_cast<QScrollArea*>(below->parentWidget());
  for (QWidget* p = below->parentWidget(); p && !area; p = p->parentWidget())
    area = qobject_cast<QScrollArea*>(p);
  ASSERT_NE(area, nullptr);
  area->ensureWidgetVisible(below);
  QApplication::processEvents();
  ASSERT_FALSE(below->visibleRegion().isEmpty());
  EXPECT_GE(below_draws, 1);
  // Out of view again, a run leaves it stale; an image of it (grab paints it) is drawn new.
  area->ensureWidgetVisible(top);
  QApplication::processEvents();
  ASSERT_TRUE(below->visibleRegion().isEmpty());
  const int hidden = below_draws;
  w.setParam("q_pos", 0.3);
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  EXPECT_EQ(below_draws, hidden);
  (void)below->grab();
  EXPECT_EQ(below_draws, hidden + 1);
}

}  // namespace
}  // namespace kfw
