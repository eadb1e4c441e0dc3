// The Tune and Sweep dialogs driven offscreen: results go through the document's undo stack,
// Apply/Revert, the scale and bound warnings, the sweep's progress, best marker, click and CSV.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QElapsedTimer>
#include <QFile>
#include <QTemporaryDir>

#include "common/gui_util.h"
#include "main_window.h"
#include "metrics_panel.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw {
namespace {

using testing::waitDone;

TEST(TuneDialog, ResultIsAnUndoableStepAndRevertRestoresTheStart) {
  MainWindow w;
  // Seed 4: on 30 s of seed 1 the bias walk lets the start-up P0 tell the scale apart (RMSE
  // 4.7 % off at ×10 against 31 % for Q alone), above the tuner's twentieth.
  ASSERT_TRUE(
      w.loadPreset("helicopter", {}, {"Q=1", "R=100", "sim.duration=30", "sim.seed=4"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const ParamValues start = w.values();
  const double rmse0 = w.result()->metrics.at("rmse");
  w.pinSnapshot("before");
  TuneDialog* d = w.openTuneDialog();
  ASSERT_NE(d, nullptr);
  // Only tunable keys are offered (not m, window, Ts).
  EXPECT_EQ(d->selected(), (QStringList{"Q", "R", "gamma"}));
  d->setSelected({"Q", "R"});
  d->setObjective("rmse");
  d->setBudget(150);
  d->start();
  ASSERT_TRUE(waitDone(d));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(d->progressValue(), d->progressMaximum());
  EXPECT_NE(w.values().at("Q"), 1.0);
  EXPECT_LT(w.result()->metrics.at("rmse"), 0.8 * rmse0);
  EXPECT_TRUE(d->message().contains("rmse = ")) << d->message().toStdString();
  // A 2-state filter's RMSE depends on Q/R only: the dialog says so.
  EXPECT_TRUE(d->message().contains("does not change when Q, R scale together"))
      << d->message().toStdString();
  EXPECT_EQ(w.document()->undo_label(), "tune");
  d->revert();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values(), start);
  EXPECT_EQ(w.snapshotCount(), 1);  // Revert leaves pinned snapshots alone
  ASSERT_TRUE(w.undo());            // undo the revert: the tuning is back
  ASSERT_TRUE(w.waitForRun());
  EXPECT_NE(w.values().at("Q"), 1.0);
  ASSERT_TRUE(w.undo());  // undo the tuning: the start
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values(), start);
  EXPECT_DOUBLE_EQ(w.result()->metrics.at("rmse"), rmse0);
}

// Acceptance: tune with the default selection and objective succeeds on every preset.
TEST(TuneDialog, DefaultObjectiveSucceedsOnEveryPreset) {
  QStringList presets = {"helicopter", "radome", "ballbeam", "underwater"};
  if (QFile::exists(QString(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv"))
    presets << "broad_imu";
  for (const QString& name : presets) {
    const std::string preset = name.toStdString();
    MainWindow w;
    ASSERT_TRUE(w.loadPreset(name).ok()) << preset;
    ASSERT_TRUE(w.waitForRun(60000)) << preset;
    TuneDialog* d = w.openTuneDialog();
    ASSERT_NE(d, nullptr) << preset;
    EXPECT_FALSE(d->selected().isEmpty()) << preset;
    d->setBudget(30);
    d->start();
    ASSERT_TRUE(waitDone(d, 120000)) << preset;
    ASSERT_NE(d->result(), nullptr) << preset << ": " << d->message().toStdString();
    EXPECT_FALSE(d->message().startsWith("⚠")) << preset << ": " << d->message().toStdString();
  }
}

// The optimum on a search bound is shown.
TEST(TuneDialog, BoundHitIsShown) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=30"}).ok());
  ASSERT_TRUE(w.waitForRun());
  TuneDialog* d = w.openTuneDialog();
  d->setSelected({"R"});
  d->setObjective("rmse");
  d->setBounds("R", 0.01, 0.1);
  d->setBudget(40);
  d->start();
  ASSERT_TRUE(waitDone(d));
  EXPECT_TRUE(d->message().contains("search bound for R")) << d->message().toStdString();
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
  d->setBounds("R", 1e-6, 1e6);
  d->setBudget(150);
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
  EXPECT_EQ(d->progressValue(), 11);
  ASSERT_GE(d->plot()->graphCount(), 1);
  EXPECT_EQ(d->plot()->graph(0)->data()->size(), 11);
  EXPECT_TRUE(d->message().contains("best rmse (lowest)")) << d->message().toStdString();

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

// The best marker follows the metric's direction: whiteness_p is best when highest.
TEST(SweepDialog, BestFollowsTheDirectionAndAClickApplies) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=30"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const ParamValues start = w.values();
  SweepDialog* d = w.openSweepDialog();
  d->setAxis(0, "R", 0.01, 100, 9);
  d->setAxis(1, "", 0, 0, 1);
  d->setMetric("whiteness_p");
  d->start();
  ASSERT_TRUE(waitDone(d));
  const SweepResult* r = d->result();
  ASSERT_NE(r, nullptr);
  double most = -1;
  for (const auto& m : r->metrics)
    most = std::max(most, m.at("whiteness_p"));
  EXPECT_EQ(r->metrics[d->bestIndex()].at("whiteness_p"), most);
  EXPECT_TRUE(d->message().contains("(highest)")) << d->message().toStdString();
  // A click applies the point as one undo step.
  d->choosePoint(2);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_DOUBLE_EQ(w.values().at("R"), r->points[2][0]);
  EXPECT_EQ(w.document()->undo_label(), "sweep point");
  ASSERT_TRUE(w.undo());
  EXPECT_EQ(w.values(), start);
  // The grid as CSV: a header and one row per point.
  QTemporaryDir dir;
  const QString csv = dir.filePath("grid.csv");
  ASSERT_TRUE(d->exportCsv(csv).ok());
  QFile f(csv);
  ASSERT_TRUE(f.open(QIODevice::ReadOnly));
  const QStringList lines = QString(f.readAll()).split('\n', Qt::SkipEmptyParts);
  ASSERT_EQ(lines.size(), 10);
  EXPECT_EQ(lines[0], "R,whiteness_p");
}

// Cancel keeps the finished points (they are shown, the best among them marked), the dialog
// sits over the plots and not over the metrics table, and a flat valley is warned of.
TEST(SweepDialog, CancelKeepsTheFinishedPointsBesideTheMetrics) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=60"}).ok());
  ASSERT_TRUE(w.waitForRun());
  SweepDialog* d = w.openSweepDialog();
  ASSERT_NE(d, nullptr);
  QApplication::processEvents();
  const QWidget* metrics = w.metricsPanel();
  const QRect table(metrics->mapToGlobal(QPoint(0, 0)), metrics->size());
  EXPECT_FALSE(d->frameGeometry().intersects(table)) << "the dialog covers the metrics";
  d->setAxis(0, "Q", 1, 1000, 60);
  d->setAxis(1, "R", 0.1, 100, 60);
  d->setMetric("rmse");
  d->start();
  QElapsedTimer clock;
  clock.start();
  while (d->progressValue() < 4 && clock.elapsed() < 60000)
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  d->cancel();
  ASSERT_TRUE(waitDone(d));
  EXPECT_TRUE(d->message().contains("cancelled after")) << d->message().toStdString();
  const SweepResult* r = d->result();
  ASSERT_NE(r, nullptr);
  std::size_t ran = 0;
  for (const auto& m : r->metrics)
    ran += m.empty() ? 0 : 1;
  EXPECT_GE(ran, 4u);
  EXPECT_LT(ran, r->points.size());
  ASSERT_LT(d->bestIndex(), r->points.size());
  EXPECT_FALSE(r->metrics[d->bestIndex()].empty()) << "the best is a finished point";
  EXPECT_TRUE(d->message().contains("best rmse")) << d->message().toStdString();
  // A parameter over a range where it changes nothing that matters: flat, and said so.
  d->setAxis(0, "gamma", 0.0, 1e-9, 8);
  d->setAxis(1, "", 0, 0, 1);
  d->start();
  ASSERT_TRUE(waitDone(d));
  EXPECT_TRUE(d->message().contains("Flat:")) << d->message().toStdString();
}

// Switching preset or quitting with unsaved changes or snapshots asks first.
TEST(MainWindowTune, UnsavedWorkIsNotThrownAwayUnasked) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=10"}).ok());
  ASSERT_TRUE(w.waitForRun());
  QStringList asked;
  bool answer = false;
  w.setConfirmHandler([&](const QString& q) {
    asked << q;
    return answer;
  });
  EXPECT_TRUE(w.confirmDiscard("Switch preset"));  // nothing to lose: no question
  EXPECT_TRUE(asked.isEmpty());
  w.pinSnapshot("a");
  EXPECT_FALSE(w.close());  // refused: the window stays
  ASSERT_EQ(asked.size(), 1);
  EXPECT_TRUE(asked[0].contains("1 pinned snapshot")) << asked[0].toStdString();
  w.setParam("Q", 5.0);
  EXPECT_FALSE(w.confirmDiscard("Switch preset"));
  EXPECT_TRUE(asked.back().contains("unsaved changes")) << asked.back().toStdString();
  answer = true;
  EXPECT_TRUE(w.close());
}

}  // namespace
}  // namespace kfw
