// The presentation controller without the workbench: a window with three plots in a grid; the
// View menu's action, presentation on (the chosen plots only, fonts × the scale) and off (the
// layout and fonts back), the chosen plots and scale through the view state, the dark theme, and
// screenshot mode leaving the timings out of the status text.
#include <gtest/gtest.h>
#include <qcustomplot.h>

#include <QAction>
#include <QApplication>
#include <QGridLayout>
#include <QLabel>
#include <QMainWindow>
#include <QMenuBar>

#include "plot_look.h"
#include "presentation_controller.h"

namespace kfw::presentation_controller_test {
namespace {

class PresentWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    auto* host = new QWidget;
    auto* grid = new QGridLayout(host);
    for (const char* name : {"a", "b", "c"}) {
      auto* p = new QCustomPlot;
      p->addGraph()->setData({0.0, 1.0, 2.0}, {1.0, 2.0, 0.5});
      grid->addWidget(p, static_cast<int>(plots.size()) / 2, static_cast<int>(plots.size()) % 2);
      plots << PlotPanel{name, QString("plot ") + name, p};
    }
    window.setCentralWidget(host);
    status = new QLabel("12 steps · run 1.2 ms · rmse = 0.5 m");
    present = new PresentationController(&window, status);
    present->setPlotSources([this] { return plots; }, [] { return QList<QCustomPlot*>(); });
    present->setScenario("probe");
    present->buildMenu(window.menuBar());
    window.resize(1000, 700);
    window.show();
    font = QApplication::font();
  }
  void TearDown() override {
    if (present->presentation()) present->setPresentation(false);
    delete status;
  }

  QMainWindow window;
  QList<PlotPanel> plots;
  QLabel* status = nullptr;
  PresentationController* present = nullptr;
  QFont font;
};

TEST_F(PresentWindow, PresentingShowsTheChosenPlotsLargerAndLeavingGivesAllBack) {
  auto* action = window.findChild<QAction*>("presentAction");
  ASSERT_NE(action, nullptr);
  present->setScale(1.5);
  action->trigger();
  ASSERT_TRUE(present->presentation());
  EXPECT_TRUE(action->isChecked());
  EXPECT_EQ(present->presentedPlots(), (QStringList{"a", "b"}));  // the first two by default
  EXPECT_FALSE(plots[0].plot->isHidden());
  EXPECT_TRUE(plots[2].plot->isHidden());
  EXPECT_DOUBLE_EQ(QApplication::font().pointSizeF(), font.pointSizeF() * 1.5);
  present->setPresentedPlots({"c"});
  EXPECT_TRUE(plots[0].plot->isHidden());
  EXPECT_FALSE(plots[2].plot->isHidden());
  present->setPresentation(false);
  EXPECT_FALSE(action->isChecked());
  for (const PlotPanel& p : plots)
    EXPECT_FALSE(p.plot->isHidden()) << p.name.toStdString();
  EXPECT_EQ(QApplication::font(), font);
}

TEST_F(PresentWindow, TheViewStateCarriesOnScaleAndPlots) {
  present->setScale(2.0);
  present->setPresentedPlots({"b", "c"});
  present->setPresentation(true);
  const QJsonValue saved = present->saveState();
  present->setPresentation(false);
  present->setScale(1.0);
  present->setPresentedPlots({"a"});
  present->restoreState(saved);
  EXPECT_TRUE(present->presentation());
  EXPECT_DOUBLE_EQ(present->scale(), 2.0);
  EXPECT_EQ(present->presentedPlots(), (QStringList{"b", "c"}));
  EXPECT_TRUE(plots[0].plot->isHidden());
}

TEST_F(PresentWindow, TheDarkThemeAndScreenshotMode) {
  present->setTheme(Theme::kDark);
  EXPECT_EQ(present->theme(), Theme::kDark);
  for (const PlotPanel& p : plots)
    EXPECT_EQ(currentTheme(p.plot), Theme::kDark) << p.name.toStdString();
  present->setTheme(Theme::kLight);
  present->setScreenshotMode(true);
  EXPECT_EQ(status->text(), "12 steps · rmse = 0.5 m");
  status->setText("13 steps · request→plots 8.0 ms");
  present->restyle();
  EXPECT_EQ(status->text(), "13 steps");
}

}  // namespace
}  // namespace kfw::presentation_controller_test
