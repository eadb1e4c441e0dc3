// Presentation mode at 1366×768: only the chosen plots, every visible title whole (its widest line
// fits the title's rect), every text of the window and the plots ≥ 14 px; leaving restores the
// window's own layout and look.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QFontInfo>
#include <QFontMetricsF>
#include <QImage>
#include <QSettings>

#include "main_window.h"
#include "plot_look.h"

namespace kfw {
namespace {

double pixels(const QFont& f, const QWidget* w) {
  return f.pointSizeF() * w->logicalDpiY() / 72.0;
}

// The smallest text of a plot, px: title, axis labels, tick labels, legend.
double smallestText(const QCustomPlot* p) {
  double s = 1e9;
  for (QCPLayoutElement* e : p->plotLayout()->elements(true)) {
    if (auto* t = qobject_cast<QCPTextElement*>(e)) s = std::min(s, pixels(t->font(), p));
  }
  for (QCPAxisRect* r : p->axisRects()) {
    for (QCPAxis* a : r->axes()) {
      if (!a->visible()) continue;
      s = std::min({s, pixels(a->labelFont(), p), pixels(a->tickLabelFont(), p)});
    }
    for (QCPLayoutElement* e : r->insetLayout()->elements(true)) {
      if (auto* l = qobject_cast<QCPLegend*>(e); l && l->visible()) {
        for (int i = 0; i < l->itemCount(); ++i)
          s = std::min(s, pixels(l->item(i)->font(), p));
      }
    }
  }
  return s;
}

class Presenting : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override { QSettings("kfw", "kfw").remove("present"); }
  void TearDown() override { QSettings("kfw", "kfw").remove("present"); }
};

TEST_P(Presenting, TitlesWholeAndTextLargeAt1366x768) {
  MainWindow w;
  auto st = w.loadPreset(GetParam());
  if (!st) GTEST_SKIP() << st.error();
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.waitForRun(60000));
  const double plain_font = smallestText(w.plots().front().plot);
  w.setPresentation(true);
  w.resize(1366, 768);
  QApplication::processEvents();
  ASSERT_TRUE(w.presentation());
  int visible = 0;
  for (const PlotPanel& p : w.plots()) {
    if (!p.plot->isVisible()) continue;
    ++visible;
    p.plot->replot();
    auto* title = p.plot->findChild<QCPTextElement*>("title");
    ASSERT_NE(title, nullptr);
    const QFontMetricsF fm(title->font());
    for (const QString& line : title->text().split('\n')) {
      EXPECT_LE(fm.horizontalAdvance(line), title->rect().width() + 0.5)
          << p.name.toStdString() << ": '" << line.toStdString() << "' is cut";
    }
    EXPECT_GE(smallestText(p.plot), 14.0) << p.name.toStdString();
  }
  EXPECT_EQ(visible, 2);  // by default the first two plots, larger
  EXPECT_EQ(w.presentedPlots().size(), 2);
  EXPECT_GE(pixels(QApplication::font(), &w), 14.0);

  // Leaving gives back every plot and the house fonts.
  w.setPresentation(false);
  QApplication::processEvents();
  for (const PlotPanel& p : w.plots())
    EXPECT_FALSE(p.plot->isHidden()) << p.name.toStdString();
  EXPECT_DOUBLE_EQ(smallestText(w.plots().front().plot), plain_font);
  EXPECT_LT(pixels(QApplication::font(), &w), 14.0);
}

INSTANTIATE_TEST_SUITE_P(Presets, Presenting,
                         ::testing::Values("helicopter", "radome", "underwater", "ballbeam",
                                           "models/range_bearing"));

TEST(Presentation, ChosenPlotsScaleAndBandsForAProjector) {
  QSettings("kfw", "kfw").remove("present");
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.waitForRun());
  ASSERT_GE(w.plots().size(), 4);
  const QString third = w.plots()[2].name, fourth = w.plots()[3].name;
  w.setPresentedPlots({third, fourth, w.plots()[0].name});
  w.setPresentation(true);
  QApplication::processEvents();
  EXPECT_FALSE(w.plots()[1].plot->isVisibleTo(&w));
  EXPECT_TRUE(w.plots()[2].plot->isVisibleTo(&w));
  // Ctrl+= makes text larger, remembered for the next window.
  const double s = w.presentationScale();
  const double before = w.plots()[0].plot->xAxis->tickLabelFont().pointSizeF();
  w.setPresentationScale(s * 1.15);
  EXPECT_GT(w.plots()[0].plot->xAxis->tickLabelFont().pointSizeF(), before);
  MainWindow other;
  EXPECT_DOUBLE_EQ(other.presentationScale(), w.presentationScale());
  // Data pens at least 2 px; band fills deeper than the pale screen fill.
  QCustomPlot* p = w.plots()[0].plot;
  bool band = false;
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->pen().style() != Qt::NoPen && p->graph(i)->visible()) {
      EXPECT_GE(p->graph(i)->pen().widthF(), 2.0);
    }
    if (p->graph(i)->brush().style() != Qt::NoBrush) {
      band = true;
      EXPECT_LT(p->graph(i)->brush().color().lightness(), 215);
    }
  }
  EXPECT_TRUE(band);
  w.setPresentation(false);
  QSettings("kfw", "kfw").remove("present");
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->brush().style() != Qt::NoBrush) {
      EXPECT_GT(p->graph(i)->brush().color().lightness(), 215);
    }
  }
}

}  // namespace
}  // namespace kfw
