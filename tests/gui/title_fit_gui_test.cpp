// On a 1366 × 768 screen, outside presentation mode, every plot title is whole: a long one wraps to
// its own cell's width (radome's LOS-error and heat-map titles were cut at both ends), and its
// lines go back to one when the window is wide again.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QApplication>
#include <QFontMetricsF>

#include "main_window.h"

namespace kfw {
namespace {

// Each line of each visible plot's title fits the title's rect; returns how many titles wrapped.
int checkTitles(MainWindow& w) {
  int wrapped = 0;
  for (const PlotPanel& p : w.plots()) {
    if (!p.plot->isVisible()) continue;
    p.plot->replot();
    auto* title = p.plot->findChild<QCPTextElement*>("title");
    if (!title) continue;
    const QFontMetricsF fm(title->font());
    const QStringList lines = title->text().split('\n');
    wrapped += lines.size() > 1 ? 1 : 0;
    for (const QString& line : lines) {
      EXPECT_LE(fm.horizontalAdvance(line), title->rect().width() + 0.5)
          << p.name.toStdString() << ": '" << line.toStdString() << "' is cut";
    }
  }
  return wrapped;
}

TEST(TitleFit, RadomeTitlesAreWholeAt1366x768AndUnwrapWhenWide) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/radome.json").ok());
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  EXPECT_GE(checkTitles(w), 1);  // at least one long title needed two lines
  // A parameter change redraws (the heat map's title is set with its data): still whole.
  w.setParam("R", 2e-6);
  ASSERT_TRUE(w.waitForRun(60000));
  QApplication::processEvents();
  checkTitles(w);
  w.resize(2400, 1000);
  QApplication::processEvents();
  EXPECT_EQ(checkTitles(w), 0);
}

}  // namespace
}  // namespace kfw
