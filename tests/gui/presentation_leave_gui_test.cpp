// Leaving presentation after switching preset gives back the window a fresh one would show
// (issue 32, item 5): every font (units, metric group headers, plot texts) and the plots' grid.
#include <gtest/gtest.h>
#include <qcustomplot.h>

#include <QApplication>
#include <QMap>
#include <QTableWidget>
#include <QTest>

#include "main_window.h"
#include "metrics_panel.h"
#include "monte_carlo_dialog.h"
#include "sweep_dialog.h"

namespace kfw {
namespace {

// Every font a user reads, by where it is: named widgets, metric rows, plot texts.
QMap<QString, double> fontsOf(MainWindow& w) {
  QMap<QString, double> out;
  for (const QWidget* c : w.findChildren<QWidget*>()) {
    if (!c->objectName().isEmpty() && c->isVisible())
      out["widget " + c->objectName()] = c->font().pointSizeF();
  }
  const MetricsPanel* m = w.metricsPanel();
  for (int r = 0; r < m->rowCount(); ++r) {
    if (const QTableWidgetItem* it = m->item(r, 0))
      out["metric " + it->text()] = it->font().pointSizeF();
  }
  for (const auto& p : w.plots()) {
    for (int i = 0; i < p.plot->plotLayout()->elementCount(); ++i) {
      if (auto* t = qobject_cast<QCPTextElement*>(p.plot->plotLayout()->elementAt(i)))
        out["plot " + p.name + " text " + t->text()] = t->font().pointSizeF();
    }
    for (const QCPAxis* a : p.plot->axisRect()->axes())
      out["plot " + p.name + " axis " + QString::number(a->axisType()) + " " + a->label()] =
          a->labelFont().pointSizeF();
    if (p.plot->legend) out["plot " + p.name + " legend"] = p.plot->legend->font().pointSizeF();
    for (int i = 0; i < p.plot->itemCount(); ++i) {
      if (auto* t = qobject_cast<QCPItemText*>(p.plot->item(i)))
        out["plot " + p.name + " item " + t->text()] = t->font().pointSizeF();
    }
  }
  return out;
}

void open(MainWindow& w, const char* preset) {
  ASSERT_TRUE(w.loadPreset(preset).ok());
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
}

TEST(PresentationLeave, AfterAPresetSwitchEveryFontAndTheGridComeBack) {
  MainWindow fresh;
  fresh.resize(1366, 768);
  fresh.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&fresh));
  open(fresh, "radome");
  QTest::qWait(50);

  MainWindow w;
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  open(w, "helicopter");
  w.presentationController()->setScale(1.5);
  w.presentationController()->setPresentation(true);
  QApplication::processEvents();
  open(w, "radome");  // switched while presenting
  w.presentationController()->setPresentation(false);
  QApplication::processEvents();
  QTest::qWait(50);

  const QMap<QString, double> want = fontsOf(fresh);
  const QMap<QString, double> got = fontsOf(w);
  int compared = 0;
  for (auto it = want.begin(); it != want.end(); ++it) {
    if (!got.contains(it.key())) continue;
    EXPECT_DOUBLE_EQ(got[it.key()], it.value()) << it.key().toStdString();
    ++compared;
  }
  EXPECT_GT(compared, 30);
  // The grid: each plot as wide and as high as in the fresh window.
  ASSERT_EQ(w.plots().size(), fresh.plots().size());
  for (int i = 0; i < w.plots().size(); ++i) {
    EXPECT_EQ(w.plots()[i].plot->size(), fresh.plots()[i].plot->size())
        << w.plots()[i].name.toStdString();
  }
}

// The dialogs' plots take the presentation's scale (their fonts were the window's normal ones).
TEST(PresentationLeave, DialogPlotsTakeThePresentationScale) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  open(w, "models/cv1d");
  w.presentationController()->setScale(1.5);
  w.presentationController()->setPresentation(true);
  QApplication::processEvents();
  for (QWidget* d : {static_cast<QWidget*>(w.openMonteCarloDialog()),
                     static_cast<QWidget*>(w.openSweepDialog())}) {
    ASSERT_TRUE(d);
    const auto plots = d->findChildren<QCustomPlot*>();
    ASSERT_FALSE(plots.isEmpty());
    for (const QCustomPlot* p : plots) {
      EXPECT_DOUBLE_EQ(p->xAxis->labelFont().pointSizeF(), 9.0 * 1.5);
      EXPECT_DOUBLE_EQ(p->xAxis->tickLabelFont().pointSizeF(), 9.0 * 1.5);
    }
    d->close();
  }
  w.presentationController()->setPresentation(false);
  for (QWidget* d : {static_cast<QWidget*>(w.openMonteCarloDialog())}) {
    for (const QCustomPlot* p : d->findChildren<QCustomPlot*>())
      EXPECT_DOUBLE_EQ(p->xAxis->labelFont().pointSizeF(), 9.0);
    d->close();
  }
}

}  // namespace
}  // namespace kfw
