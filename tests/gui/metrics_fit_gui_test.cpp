// At 1366×768 the metrics table shows the primary metric and its whole group without scrolling
// (the table takes the height from the parameters above it, which scroll), for every built-in
// scenario; a splitter the user moved is left where the user put it.
#include <gtest/gtest.h>

#include <QApplication>
#include <QScrollBar>
#include <QSplitter>
#include <QTest>

#include "core/metrics.h"
#include "main_window.h"
#include "metrics_panel.h"

namespace kfw {
namespace {

// The last row of the primary's group, found from the table's own roles and the declaration.
int primaryGroupEnd(const MainWindow& w) {
  const MetricsPanel* m = w.metricsPanel();
  const std::string key = m->item(0, 0)->data(MetricsPanel::kKeyRole).toString().toStdString();
  const QString group = group_name(describe_metric(*w.scenario(), key, w.result().get()).group);
  int end = 0;
  bool inside = false;
  for (int r = 1; r < m->rowCount(); ++r) {
    const QVariant g = m->item(r, 0)->data(MetricsPanel::kGroupRole);
    if (g.isValid()) {
      if (inside) break;
      inside = g.toString() == group;
    } else if (inside) {
      end = r;
    }
  }
  return end;
}

// Rows 0..end of the table lie inside its viewport, unscrolled.
void expectRowsVisible(const MetricsPanel* m, int end) {
  EXPECT_EQ(m->verticalScrollBar()->value(), 0);
  const QRect view = m->viewport()->rect();
  for (int r = 0; r <= end; ++r) {
    const QRect cell = m->visualRect(m->model()->index(r, 0));
    EXPECT_TRUE(view.contains(cell))
        << "row " << r << " of 0.." << end << " is cut: cell y " << cell.top() << ".."
        << cell.bottom() << ", view height " << view.height();
  }
}

TEST(MetricsFit, AResizedWindowReFitsWithoutANewRun) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("radome").ok());
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  // The table squeezed by a layout change (not by the user: no splitterMoved), then a resize.
  auto* split = w.findChild<QSplitter*>("leftSplit");
  ASSERT_NE(split, nullptr);
  const QList<int> sizes = split->sizes();
  split->setSizes({sizes[0] + sizes[1] - 60, 60});
  const QString before = w.metricsPanel()->item(0, 1)->text();
  w.resize(1400, 780);
  QTest::qWait(100);  // the resize, the re-fit after it, the splitter's layout
  EXPECT_EQ(w.metricsPanel()->item(0, 1)->text(), before);  // the same run, no new one
  expectRowsVisible(w.metricsPanel(), primaryGroupEnd(w));
}

TEST(MetricsFit, PrimaryGroupVisibleWithoutScrollingAt1366x768) {
  for (const char* preset : {"radome", "underwater", "helicopter", "ballbeam"}) {
    SCOPED_TRACE(preset);
    MainWindow w;
    ASSERT_TRUE(w.loadPreset(preset).ok());
    w.resize(1366, 768);
    w.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
    ASSERT_TRUE(w.waitForRun(60000));
    QApplication::processEvents();
    EXPECT_EQ(w.size(), QSize(1366, 768));
    MetricsPanel* m = w.metricsPanel();
    ASSERT_GT(m->rowCount(), 2);
    const int end = primaryGroupEnd(w);
    EXPECT_GE(end, 1) << "the primary's group has more rows than the primary";
    EXPECT_EQ(m->verticalScrollBar()->value(), 0);
    const QRect view = m->viewport()->rect();
    for (int r = 0; r <= end; ++r) {
      const QRect cell = m->visualRect(m->model()->index(r, 0));
      EXPECT_TRUE(view.contains(cell))
          << "row " << r << " of 0.." << end << " is cut: cell y " << cell.top() << ".."
          << cell.bottom() << ", view height " << view.height();
    }
  }
}

TEST(MetricsFit, AUserMovedSplitterStays) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("radome", {}, {"sim.duration=10"}).ok());
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.waitForRun(60000));
  auto* split = w.findChild<QSplitter*>("leftSplit");
  ASSERT_NE(split, nullptr);
  // A drag of the handle (what splitterMoved reports) to a small table.
  QList<int> sizes = split->sizes();
  const int total = sizes[0] + sizes[1];
  split->setSizes({total - 150, 150});
  emit split->splitterMoved(total - 150, 1);
  w.setParam("Kp", 0.2);
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  EXPECT_LE(split->sizes()[1], 160);
}

}  // namespace
}  // namespace kfw
