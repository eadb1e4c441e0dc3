// The ballbeam window driven as a user would, offscreen: the detection check box and the filter
// combo re-run live, the step plot overlays the three closed-loop runs, the α-β operating point
// follows Q and R, export writes every plot, pinned tunings leave ghosts cut at the cursor.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCheckBox>
#include <QComboBox>
#include <QFile>
#include <QSlider>
#include <QTemporaryDir>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "scenarios/ballbeam/ballbeam_result.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::plotNamed;

std::vector<double> values(QCPGraph* g) {
  std::vector<double> v;
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it)
    v.push_back(it->value);
  return v;
}

class BallbeamWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/ballbeam.json").ok());
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(w.result());
  }
  std::shared_ptr<const ballbeam::BallbeamResult> result() const {
    return std::dynamic_pointer_cast<const ballbeam::BallbeamResult>(w.result());
  }
  MainWindow w;
};

TEST_F(BallbeamWindow, StepPlotOverlaysNoiseFreeDetectionOnAndOff) {
  QCustomPlot* step = plotNamed(w, "step");
  ASSERT_NE(step, nullptr);
  QCPGraph* clean = graphNamed(step, "noise-free");
  QCPGraph* on = graphNamed(step, "detection on");
  QCPGraph* off = graphNamed(step, "detection off");
  ASSERT_TRUE(clean && on && off);
  const auto c = values(clean), a = values(on), b = values(off);
  ASSERT_EQ(c.size(), w.result()->steps());
  ASSERT_EQ(a.size(), c.size());
  // Without the circuit the ball of the default seed falls off at 5.11 s: its curve ends there.
  ASSERT_GT(b.size(), 100u);
  ASSERT_LE(b.size(), c.size());
  double gap_on = 0, gap_off = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    gap_on = std::max(gap_on, std::abs(a[i] - c[i]));
  for (std::size_t i = 0; i < b.size(); ++i)
    gap_off = std::max(gap_off, std::abs(b[i] - c[i]));
  EXPECT_LT(5 * gap_on, gap_off);  // Figs. 8, 9
}

TEST_F(BallbeamWindow, DetectionCheckBoxRerunsLive) {
  auto* check = w.findChild<QCheckBox*>("check.detection");
  ASSERT_NE(check, nullptr);
  ASSERT_TRUE(check->isChecked());
  QCPGraph* est = graphNamed(plotNamed(w, "position"), "estimate of x");
  ASSERT_NE(est, nullptr);
  const auto before = values(est);
  const double rmse_on = w.result()->metrics.at("rmse");
  check->setChecked(false);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("detection"), 0.0);
  EXPECT_NE(values(est), before);
  EXPECT_GT(w.result()->metrics.at("rmse"), 5 * rmse_on);
  EXPECT_EQ(w.result()->metrics.at("rmse"), w.result()->metrics.at("rmse_pos_detect_off"));
}

TEST_F(BallbeamWindow, FilterComboSwitchesToTheTimeVaryingKf) {
  auto* combo = w.findChild<QComboBox*>("combo.filter");
  ASSERT_NE(combo, nullptr);
  EXPECT_EQ(combo->currentText(), "steady");
  combo->setCurrentIndex(combo->findText("kf"));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("filter"), 0.0);
  // The KF's gain starts large and settles on the α of the closed form between contact losses;
  // right after a skipped update it is larger again (P grew over the missing samples).
  auto r = result();
  ASSERT_TRUE(r);
  const auto& tr = r->trace;
  EXPECT_GT(tr.K1[1], r->alpha * 1.5);
  double k_min = 1.0, k_after_gap = 0.0;
  for (std::size_t k = tr.K1.size() / 2; k < tr.K1.size(); ++k) {
    if (!std::isfinite(tr.K1[k])) continue;
    k_min = std::min(k_min, tr.K1[k]);
    if (tr.flagged[k - 1] == 1.0) k_after_gap = std::max(k_after_gap, tr.K1[k]);
  }
  EXPECT_NEAR(k_min, r->alpha, 1e-3);
  EXPECT_GT(k_after_gap, r->alpha * 1.2);
}

TEST_F(BallbeamWindow, OperatingPointFollowsR) {
  QCPGraph* op = graphNamed(plotNamed(w, "gain_curve"), "operating point");
  ASSERT_NE(op, nullptr);
  ASSERT_EQ(op->data()->size(), 2);
  const double l0 = op->data()->constBegin()->key;
  EXPECT_NEAR(l0, 0.0354, 5e-5);
  const double R0 = w.values().at("R");
  w.setParam("R", R0 * 100);
  ASSERT_TRUE(w.waitForRun());
  const double l1 = op->data()->constBegin()->key;
  EXPECT_NEAR(l1, l0 / 10, 1e-6 * l0);  // λ ∝ 1/√R
}

TEST_F(BallbeamWindow, ReplayRevealsUpToTheCursorAndExportWritesEveryPlot) {
  QCPGraph* est = graphNamed(plotNamed(w, "position"), "estimate of x");
  w.transport()->seek(199);
  EXPECT_EQ(est->data()->size(), 200);
  w.transport()->setShowAll(true);
  EXPECT_EQ(static_cast<std::size_t>(est->data()->size()), w.result()->steps());
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  for (const QString& f : *files)
    EXPECT_GT(QFile(f).size(), 2000) << f.toStdString();
}

TEST_F(BallbeamWindow, PinnedTuningLeavesGhostsCutAtTheCursor) {
  const auto pinned = result();
  ASSERT_TRUE(pinned);
  w.pinSnapshot("tight");
  w.setParam("R", w.values().at("R") * 100);
  ASSERT_TRUE(w.waitForRun());
  ASSERT_EQ(w.snapshotCount(), 1);
  QCustomPlot* pos = plotNamed(w, "position");
  QCustomPlot* step = plotNamed(w, "step");
  QCPGraph* est = graphNamed(pos, "estimate of x [pinned: tight]");
  QCPGraph* resp = graphNamed(step, "[pinned: tight] (detection on)");
  ASSERT_TRUE(est && resp);
  EXPECT_LT(est->pen().color().alpha(), 255);  // faded
  // The ghosts hold the pinned run, not the live one.
  const std::size_t n = pinned->steps();
  ASSERT_EQ(values(est).size(), n);
  ASSERT_EQ(values(resp).size(), n);
  EXPECT_EQ(values(est), pinned->trace.x_hat);
  EXPECT_EQ(values(resp), pinned->x_detect_on);
  EXPECT_NE(values(est), values(graphNamed(pos, "estimate of x")));
  // Replay cuts them at the cursor like the live curves.
  w.transport()->seek(199);
  EXPECT_EQ(est->data()->size(), 200);
  EXPECT_EQ(resp->data()->size(), 200);
  w.transport()->setShowAll(true);
  EXPECT_EQ(static_cast<std::size_t>(est->data()->size()), n);
  // A second pin adds a pair; clearing removes every ghost.
  w.setParam("detection", 0.0);
  ASSERT_TRUE(w.waitForRun());
  w.pinSnapshot("no circuit");
  EXPECT_NE(graphNamed(pos, "estimate of x [pinned: tight]"), nullptr);
  QCPGraph* off = graphNamed(step, "[pinned: no circuit] (detection off)");
  ASSERT_NE(off, nullptr);
  EXPECT_EQ(values(off), result()->x_detect_off);
  const int graphs = step->graphCount();
  w.clearSnapshots();
  EXPECT_EQ(step->graphCount(), graphs - 2);
  EXPECT_EQ(graphNamed(pos, "estimate of x [pinned: tight]"), nullptr);
  EXPECT_EQ(graphNamed(step, "[pinned: no circuit] (detection off)"), nullptr);
}

TEST_F(BallbeamWindow, LegendsUsePlainLabels) {
  // x̂ (combining circumflex) and x_c do not render at the legend's size.
  for (const auto& panel : w.plots()) {
    for (int i = 0; i < panel.plot->graphCount(); ++i) {
      const QString name = panel.plot->graph(i)->name();
      EXPECT_FALSE(name.contains(QChar(0x0302))) << name.toStdString();
      EXPECT_FALSE(name.contains('_')) << name.toStdString();
    }
  }
}

TEST_F(BallbeamWindow, StartUpTransientDoesNotSetTheInnovationAxis) {
  auto r = result();
  ASSERT_TRUE(r);
  // Steady innovations are a few mm; the start-up band (P0) reaches ±0.2 m.
  double late = 0.0;
  for (std::size_t k = r->steps() / 10; k < r->steps(); ++k) {
    if (std::isfinite(r->trace.S[k])) late = std::max(late, 2.0 * std::sqrt(r->trace.S[k]));
  }
  const QCPRange y = plotNamed(w, "innovation")->yAxis->range();
  EXPECT_LT(y.upper, 3.0 * late);
  EXPECT_GT(y.upper, late);
}

}  // namespace
}  // namespace kfw
