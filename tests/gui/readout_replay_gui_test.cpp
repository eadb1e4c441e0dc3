// The readout follows the replay cursor: after a seek, every time plot shows the cursor line at
// the replay time and the curves' values there, equal to the run's arrays (while playing, the
// line only, the values once paused); a mouse
// over a plot takes over, and leaving gives the replay back; at the end of the run (nothing
// replayed) no readout is shown.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QMouseEvent>
#include <QRegularExpression>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "plot_kit.h"
#include "plot_readout.h"
#include "plot_zoom.h"
#include "transport_bar.h"

namespace kfw {
namespace {

// The number after "NAME: " in a readout text; NaN when absent.
double shown(const QString& text, const QString& name) {
  for (const QString& line : text.split('\n')) {
    if (line.startsWith(name + ": ")) return line.mid(name.size() + 2).toDouble();
  }
  return std::nan("");
}

void expectNear5(double shown_value, double truth, const std::string& what) {
  // The label shows 5 significant digits.
  EXPECT_NEAR(shown_value, truth, 1e-4 * std::max(1.0, std::fabs(truth))) << what;
}

class ReadoutReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
    w.resize(1366, 768);
    w.show();
    ASSERT_TRUE(w.waitForRun());
    r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
    ASSERT_TRUE(r);
    angle = testing::plotNamed(w, "state.theta");
    ASSERT_NE(angle, nullptr);
    readout = w.zoom()->readout();
    ASSERT_NE(readout, nullptr);
  }
  // Every time plot: the line at the replay step's time and its label names that time.
  void expectReplayAt(std::size_t k) {
    int plots = 0;
    for (const auto& p : w.plots()) {
      if (!plot::isTimePlot(p.plot)) continue;
      ++plots;
      EXPECT_DOUBLE_EQ(readout->lineAt(p.plot), r->t[k]) << p.name.toStdString();
      const QString text = readout->text(p.plot);
      EXPECT_TRUE(text.startsWith(QString("t = %1 s").arg(r->t[k], 0, 'g', 5)))
          << p.name.toStdString() << ": " << text.toStdString();
    }
    EXPECT_GE(plots, 3);
  }
  MainWindow w;
  std::shared_ptr<const model::ModelResult> r;
  QCustomPlot* angle = nullptr;
  plot::PlotReadout* readout = nullptr;
};

TEST_F(ReadoutReplay, ASeekShowsTheRunsValuesAtTheReplayTime) {
  // The first run: the cursor at the end, the whole run drawn, no replay readout.
  EXPECT_TRUE(std::isnan(readout->lineAt(angle)));
  EXPECT_TRUE(readout->text(angle).isEmpty());
  for (std::size_t k : {std::size_t{321}, r->t.size() / 3, std::size_t{5}}) {
    w.transport()->seek(k);
    expectReplayAt(k);
    const QString text = readout->text(angle);
    expectNear5(shown(text, "estimate of theta"), r->x[0][k],
                "estimate at step " + std::to_string(k));
    if (std::isfinite(r->truth[0][k])) expectNear5(shown(text, "truth"), r->truth[0][k], "truth");
  }
  // A parameter change re-runs: the readout shows the new run's values at the same time.
  const std::size_t k = w.transport()->index();
  w.setParam("R", w.values().at("R") * 30.0);
  ASSERT_TRUE(w.waitForRun());
  r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_EQ(w.transport()->index(), k);
  expectReplayAt(k);
  expectNear5(shown(readout->text(angle), "estimate of theta"), r->x[0][k], "after the re-run");
  // To the end: nothing replayed, nothing shown.
  w.transport()->seek(static_cast<std::size_t>(-1));
  EXPECT_TRUE(std::isnan(readout->lineAt(angle)));
  EXPECT_TRUE(readout->text(angle).isEmpty());
}

TEST_F(ReadoutReplay, TheMouseTakesOverAndLeavingGivesTheReplayBack) {
  w.transport()->seek(200);
  expectReplayAt(200);
  QCustomPlot* other = nullptr;
  for (const auto& p : w.plots()) {
    if (p.plot != angle && plot::isTimePlot(p.plot)) other = p.plot;
  }
  ASSERT_NE(other, nullptr);
  // The mouse over the angle plot's data, at another time.
  const QRect rect = angle->axisRect()->rect();
  const QPointF pos(rect.left() + rect.width() * 0.75, rect.center().y());
  QMouseEvent move(QEvent::MouseMove, pos, angle->mapToGlobal(pos), Qt::NoButton, Qt::NoButton,
                   Qt::NoModifier);
  QApplication::sendEvent(angle, &move);
  EXPECT_TRUE(readout->hovering());
  const double mouse_t = angle->xAxis->pixelToCoord(pos.x());
  EXPECT_DOUBLE_EQ(readout->lineAt(angle), mouse_t);
  EXPECT_DOUBLE_EQ(readout->lineAt(other), mouse_t);  // the line on every time plot
  EXPECT_TRUE(readout->text(other).isEmpty());        // values on the hovered plot only
  // The replay moves on while the mouse stays: the mouse's readout stays.
  w.transport()->seek(300);
  EXPECT_DOUBLE_EQ(readout->lineAt(angle), mouse_t);
  QEvent leave(QEvent::Leave);
  QApplication::sendEvent(angle, &leave);
  EXPECT_FALSE(readout->hovering());
  expectReplayAt(300);
}

TEST_F(ReadoutReplay, FollowsWhilePlaying) {
  w.transport()->seek(0);
  w.transport()->play();
  ASSERT_TRUE(w.transport()->playing());
  QElapsedTimer clock;
  clock.start();
  int checked = 0;
  std::size_t last = 0;
  while (clock.elapsed() < 1500 && checked < 5) {
    QApplication::processEvents(QEventLoop::AllEvents, 20);
    const std::size_t k = w.transport()->index();
    if (k == last || !w.transport()->playing()) continue;
    last = k;
    ++checked;
    EXPECT_DOUBLE_EQ(readout->lineAt(angle), r->t[k]) << "step " << k;
    // Playing: the line only, no box over the data on every plot (issue 32, item 7).
    for (const auto& p : w.plots())
      EXPECT_TRUE(readout->text(p.plot).isEmpty()) << p.name.toStdString();
  }
  w.transport()->pause();
  EXPECT_GE(checked, 2) << "the replay did not move";
  // Paused: the values at the paused step, inside the plot.
  const std::size_t k = w.transport()->index();
  expectNear5(shown(readout->text(angle), "estimate of theta"), r->x[0][k],
              "paused, step " + std::to_string(k));
}

}  // namespace
}  // namespace kfw
