// The Tune and Sweep dialogs driven offscreen: the result reaches the sliders; the sweep plots.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QFile>

#include "main_window.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw {
namespace {

template <typename D>
bool waitDone(D* d, int ms = 60000) {
  QDeadlineTimer t(ms);
  while (d->running()) {
    if (t.hasExpired()) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
  }
  QCoreApplication::processEvents();
  return true;
}

TEST(TuneDialog, ResultIsWrittenBackToTheSliders) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"Q=1", "R=100", "sim.duration=30"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const double rmse0 = w.result()->metrics.at("rmse");
  TuneDialog* d = w.openTuneDialog();
  ASSERT_NE(d, nullptr);
  d->setSelected({"Q", "R"});
  d->setObjective("rmse");
  d->start();
  ASSERT_TRUE(waitDone(d));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_NE(w.values().at("Q"), 1.0);
  EXPECT_LT(w.result()->metrics.at("rmse"), 0.8 * rmse0);
  EXPECT_TRUE(d->message().contains("rmse = ")) << d->message().toStdString();
}

// On the real log the accelerometer's error is coloured: a truth-free tuning must warn.
TEST(TuneDialog, TruthFreeTuningOnColouredInnovationsWarns) {
  const QString data =
      QString(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
  if (!QFile::exists(data)) GTEST_SKIP() << "shared data not present";
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("broad_imu").ok());
  ASSERT_TRUE(w.waitForRun());
  TuneDialog* d = w.openTuneDialog();
  d->setSelected({"Q", "R"});
  d->setObjective("nll");
  d->start();
  ASSERT_TRUE(waitDone(d, 120000));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_LT(w.result()->metrics.at("whiteness_p"), 0.01);
  EXPECT_TRUE(d->message().contains("not white")) << d->message().toStdString();
  // Trusting the accelerometer: far worse than the preset's 1.64°.
  EXPECT_GT(w.result()->metrics.at("rmse"), 4.0);
}

TEST(SweepDialog, OneAndTwoParameterSweepsPlot) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=30"}).ok());
  ASSERT_TRUE(w.waitForRun());
  SweepDialog* d = w.openSweepDialog();
  ASSERT_NE(d, nullptr);
  d->setAxis(0, "gamma", 0.0, 0.05, 11);
  d->setAxis(1, "", 0, 0, 1);
  d->setMetric("rmse");
  d->start();
  ASSERT_TRUE(waitDone(d));
  ASSERT_GE(d->plot()->graphCount(), 1);
  EXPECT_EQ(d->plot()->graph(0)->data()->size(), 11);
  EXPECT_TRUE(d->message().contains("minimum rmse")) << d->message().toStdString();

  d->setAxis(0, "Q", 1, 1000, 8);
  d->setAxis(1, "R", 0.1, 100, 6);
  d->start();
  ASSERT_TRUE(waitDone(d));
  auto* map = qobject_cast<QCPColorMap*>(d->plot()->plottable(0));
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->data()->keySize(), 8);
  EXPECT_EQ(map->data()->valueSize(), 6);
  EXPECT_TRUE(std::isfinite(map->data()->cell(3, 3)));
}

}  // namespace
}  // namespace kfw
