// The replay controller without a main window: a window with a transport bar and the model's
// plots; the replay keys step the cursor (not while typing), the view is drawn up to it, the
// readout follows it, the following window sets every time plot's range, and the position
// survives a save and restore.
#include <gtest/gtest.h>
#include <qcustomplot.h>

#include <QGridLayout>
#include <QLineEdit>
#include <QTest>
#include <QVBoxLayout>
#include <cmath>

#include "document/document.h"
#include "plot_kit.h"
#include "plot_readout.h"
#include "plot_zoom.h"
#include "replay_controller.h"
#include "transport_bar.h"

namespace kfw::replay_controller_test {
namespace {

// A window holding the model's plots, a text field and a transport bar, and one run drawn.
class ReplayWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    auto doc = Document::open("models/cv1d", std::nullopt, {"sim.duration=10"});
    ASSERT_TRUE(doc.ok());
    const ParamValues values = doc->values();
    auto data = doc->scenario().simulate(values);
    ASSERT_TRUE(data.ok());
    auto run = doc->scenario().run(*data, values);
    ASSERT_TRUE(run.ok());
    result = *run;
    auto* lay = new QVBoxLayout(&window);
    auto* host = new QWidget;
    auto* grid = new QGridLayout(host);
    lay->addWidget(host, 1);
    text = new QLineEdit;
    lay->addWidget(text);
    transport = new TransportBar;
    lay->addWidget(transport);
    view = views().make(doc->scenario().name());
    ASSERT_TRUE(view);
    view->setScenario(doc->scenario_ptr());
    plots = view->createPlots(host);
    ASSERT_FALSE(plots.isEmpty());
    for (int i = 0; i < plots.size(); ++i)
      grid->addWidget(plots[i].plot, i / 2, i % 2);
    replay = new ReplayController(transport, nullptr, &window);
    zoom = new plot::ZoomGroup(
        plots, [this] { replay->redraw(); }, host);
    replay->setView(view.get(), plots, zoom);
    view->setDataset(std::make_shared<const Dataset>(std::move(*data)));
    view->setResult(result, values);
    replay->setResult(result);
    window.resize(1000, 700);
    window.show();
  }

  // The largest time the first time plot's first graph draws.
  double lastDrawnTime() const {
    for (const PlotPanel& p : plots) {
      if (!plot::isTimePlot(p.plot) || p.plot->graphCount() == 0) continue;
      const auto* g = p.plot->graph(0);
      return g->data()->isEmpty() ? -1.0 : (g->data()->constEnd() - 1)->key;
    }
    return -1.0;
  }

  QWidget window;
  QLineEdit* text = nullptr;
  TransportBar* transport = nullptr;
  ReplayController* replay = nullptr;
  plot::ZoomGroup* zoom = nullptr;
  std::unique_ptr<ScenarioView> view;
  QList<PlotPanel> plots;
  std::shared_ptr<const RunResult> result;
};

TEST_F(ReplayWindow, TheKeysStepTheCursorAndTheViewIsDrawnUpToIt) {
  const std::size_t last = result->steps() - 1;
  EXPECT_EQ(transport->index(), last);  // a first run shows everything
  QTest::keyClick(&window, Qt::Key_Home);
  EXPECT_EQ(transport->index(), 0u);
  for (int i = 0; i < 3; ++i)
    QTest::keyClick(&window, Qt::Key_Right);
  QTest::keyClick(&window, Qt::Key_Left);
  EXPECT_EQ(transport->index(), 2u);
  EXPECT_LE(lastDrawnTime(), result->t[2] + 1e-9);
  // The readout shows the replay time while the cursor is before the end.
  ASSERT_NE(zoom->readout(), nullptr);
  EXPECT_EQ(zoom->readout()->replayTime(), result->t[2]);
  QTest::keyClick(text, Qt::Key_End);  // typing: the text field's key
  EXPECT_EQ(transport->index(), 2u);
  QTest::keyClick(&window, Qt::Key_End);
  EXPECT_EQ(transport->index(), last);
  EXPECT_TRUE(std::isnan(zoom->readout()->replayTime()));
  EXPECT_GE(lastDrawnTime(), result->t[last - 1]);
  QTest::keyClick(&window, Qt::Key_Space);
  EXPECT_TRUE(transport->playing());
  QTest::keyClick(&window, Qt::Key_Space);
  EXPECT_FALSE(transport->playing());
}

TEST_F(ReplayWindow, TheFollowingWindowSetsEveryTimePlotsRange) {
  replay->applyTimeWindow(2.0, 4.0);
  int time_plots = 0;
  for (const PlotPanel& p : plots) {
    if (!plot::isTimePlot(p.plot)) continue;
    ++time_plots;
    EXPECT_EQ(p.plot->xAxis->range().lower, 2.0) << p.name.toStdString();
    EXPECT_EQ(p.plot->xAxis->range().upper, 4.0) << p.name.toStdString();
  }
  EXPECT_GT(time_plots, 0);
  replay->applyTimeWindow(4.0, 4.0);  // empty: no change
  EXPECT_EQ(plots.front().plot->xAxis->range().upper, 4.0);
}

TEST_F(ReplayWindow, ThePositionSurvivesSaveAndRestore) {
  transport->seek(5);
  const QJsonValue saved = replay->saveState();
  transport->seek(0);
  replay->restoreState(saved);
  EXPECT_EQ(transport->index(), 5u);
  EXPECT_LE(lastDrawnTime(), result->t[5] + 1e-9);
  // A new run keeps the cursor time.
  EXPECT_FALSE(replay->setResult(result));
  EXPECT_EQ(transport->index(), 5u);
}

}  // namespace
}  // namespace kfw::replay_controller_test
