// Model presets (presets/models/) in the real window, offscreen: each opens with the plots its
// model declares, a parameter change re-runs and redraws, the gain curve of an LTI model shows the
// live operating point at the DARE gain, and Consistency, Tune, Sweep and export work on them.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QComboBox>
#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <cmath>

#include "common/gui_util.h"
#include "common/plot_probe.h"
#include "consistency_panel.h"
#include "experiment/gain_curve.h"
#include "main_window.h"
#include "model/model_scenario.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::graphValues;
using testing::plotNamed;

QString modelPreset(const char* name) {
  return QString(KFW_SOURCE_DIR) + "/presets/models/" + name + ".json";
}

using testing::waitDone;

// Relative 1e-9 with an absolute floor of 1e-12 (the comparison).
void expectNear(double a, double b, const std::string& what) {
  EXPECT_LE(std::abs(a - b), std::max(1e-12, 1e-9 * std::abs(b)))
      << what << ": " << a << " vs " << b;
}

class ModelPresets : public ::testing::TestWithParam<const char*> {};

TEST_P(ModelPresets, OpensWithItsPlotsRedrawsAndExports) {
  MainWindow w;
  auto st = w.loadPreset(modelPreset(GetParam()));
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  ASSERT_TRUE(w.result()) << w.lastError().toStdString();
  auto spec = model_layout_of(*w.scenario());
  ASSERT_TRUE(spec);

  // One plot per state, per measurement component (measured and innovation), per channel (NIS).
  for (const auto& s : spec->states) {
    QCustomPlot* p = plotNamed(w, QString::fromStdString("state." + s.name));
    ASSERT_NE(p, nullptr) << s.name;
    QCPGraph* est = graphNamed(p, QString::fromStdString("estimate of " + s.name));
    ASSERT_NE(est, nullptr);
    EXPECT_GT(est->data()->size(), 10u) << s.name;
  }
  for (const auto& c : spec->channels) {
    EXPECT_NE(plotNamed(w, QString::fromStdString("nis." + c.name)), nullptr) << c.name;
    for (const auto& r : c.roles) {
      EXPECT_NE(plotNamed(w, QString::fromStdString("measured." + c.name + "." + r.name)), nullptr);
      EXPECT_NE(plotNamed(w, QString::fromStdString("innovation." + c.name + "." + r.name)),
                nullptr);
    }
  }
  ASSERT_NE(plotNamed(w, "gain"), nullptr);
  EXPECT_EQ(plotNamed(w, "gain_curve") != nullptr, spec->time_invariant);

  // A parameter change re-runs and redraws the first state's estimate.
  QCPGraph* est = graphNamed(plotNamed(w, QString::fromStdString("state." + spec->states[0].name)),
                             QString::fromStdString("estimate of " + spec->states[0].name));
  const std::vector<double> before = graphValues(est);
  const std::string key = w.primaryParameter();
  const ParamSpec* ps = w.scenario()->params().find(key);
  ASSERT_NE(ps, nullptr) << key;
  const double v = w.values().at(key);
  w.setParam(key, v * 10.0 <= ps->max ? v * 10.0 : v / 10.0);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_NE(graphValues(est), before) << key;

  // Consistency works on a model preset, whiteness included: a channel of several components
  // (a 2-D position fix) is tested component by component (issue 27).
  w.consistency()->refresh();
  EXPECT_TRUE(w.consistency()->summary().contains("mean NIS"))
      << w.consistency()->summary().toStdString();
  EXPECT_TRUE(w.consistency()->summary().contains("Ljung–Box"))
      << w.consistency()->summary().toStdString();

  // Export writes every plot, each with coloured content.
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  EXPECT_EQ(files->filter("_consistency_whiteness").size(),
            static_cast<qsizetype>(spec->channels.size()));
  for (const QString& f : *files) {
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    const int colored = testing::colouredPixels(f);
    EXPECT_GT(colored, 10) << "no coloured content in " << f.toStdString();
  }
}

INSTANTIATE_TEST_SUITE_P(Models, ModelPresets,
                         ::testing::Values("cv1d", "cv2d", "ca1d", "singer", "helicopter_indirect",
                                           "pendulum", "range_bearing"));

// The preset picker lists the model library beside the built-in scenarios.
TEST(ModelView, PresetPickerListsTheModels) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=5"}).ok());
  auto* picker = w.findChild<QComboBox*>("presets");
  ASSERT_NE(picker, nullptr);
  EXPECT_GE(picker->findText("models/cv1d"), 0);
  EXPECT_GE(picker->findText("helicopter"), 0);
}

// The gain curve of an LTI model: its operating point is the DARE gain at the live values, and
// it follows a slider and the curve's parameter.
TEST(ModelView, GainCurveShowsTheLiveOperatingPointAtTheDareGain) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("cv1d"), {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  auto check = [&](const std::string& curve_key) {
    QCPGraph* op = graphNamed(plotNamed(w, "gain_curve"), "operating point");
    ASSERT_NE(op, nullptr);
    auto dare = w.scenario()->gain(w.values(), w.dataset().get());
    ASSERT_TRUE(dare.ok()) << dare.error();
    const std::vector<double> ys = graphValues(op);
    ASSERT_EQ(ys.size(), 2u);  // K[x, z], K[v, z]
    expectNear(ys[0], dare->at("K.v.z"), "K.v.z");
    expectNear(ys[1], dare->at("K.x.z"), "K.x.z");
    for (auto it = op->data()->constBegin(); it != op->data()->constEnd(); ++it)
      EXPECT_DOUBLE_EQ(it->key, w.values().at(curve_key));
    // The operating point lies on the curve: the curve through it at the same value agrees.
    auto curve = gain_curve(*w.scenario(), w.values(), curve_key, 5, w.dataset().get());
    ASSERT_TRUE(curve.ok());
    for (std::size_t e = 0; e < curve->entries.size(); ++e)
      expectNear(curve->at[e], dare->at(curve->entries[e]), curve->entries[e]);
  };
  check("sigma_a");
  w.setParam("sigma_r", 0.5);
  ASSERT_TRUE(w.waitForRun());
  check("sigma_a");
  auto* combo = w.findChild<QComboBox*>("gainCurveParameter");
  ASSERT_NE(combo, nullptr);
  combo->setCurrentIndex(combo->findData("sigma_r"));
  check("sigma_r");
  // The curve has points over the whole declared range of σ_r (log-spaced).
  QCPGraph* k = graphNamed(plotNamed(w, "gain_curve"), "K[x, z] (–)");  // m/m (issue 27)
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->data()->size(), 100);
}

// A nonlinear model has no steady state: no gain curve is drawn (kfw-cli gain says why), and the
// gains over time are the EKF's.
TEST(ModelView, NonlinearModelHasNoGainCurve) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("range_bearing"), {}, {"sim.duration=10"}).ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(plotNamed(w, "gain_curve"), nullptr);
  EXPECT_EQ(w.findChild<QComboBox*>("gainCurveParameter"), nullptr);
  QCustomPlot* gain = plotNamed(w, "gain");
  ASSERT_NE(gain, nullptr);
  QCPGraph* k = graphNamed(gain, "K[px, range] (–)");  // m/m (issue 27)
  ASSERT_NE(k, nullptr);
  EXPECT_GT(k->data()->size(), 10);
}

TEST(ModelView, TuneAndSweepWorkOnAModelPreset) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("cv1d"), {}, {"sim.duration=30", "sigma_a=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const double rmse0 = w.result()->metrics.at("rmse");
  TuneDialog* d = w.openTuneDialog();
  ASSERT_NE(d, nullptr);
  d->setSelected({"sigma_a"});
  d->setObjective("rmse");
  d->start();
  ASSERT_TRUE(waitDone(d));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_NE(w.values().at("sigma_a"), 20.0);
  EXPECT_LT(w.result()->metrics.at("rmse"), rmse0);

  SweepDialog* s = w.openSweepDialog();
  ASSERT_NE(s, nullptr);
  s->setAxis(0, "sigma_a", 0.1, 10, 7);
  s->setAxis(1, "", 0, 0, 1);
  s->setMetric("rmse");
  s->start();
  ASSERT_TRUE(waitDone(s));
  ASSERT_GE(s->plot()->graphCount(), 1);
  EXPECT_EQ(s->plot()->graph(0)->data()->size(), 7);
}

// Pinned snapshots draw as ghosts in every state plot.
TEST(ModelView, PinnedSnapshotsDrawAsGhosts) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("cv1d"), {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  w.pinSnapshot("base");
  w.setParam("sigma_a", 5.0);
  ASSERT_TRUE(w.waitForRun());
  for (const char* s : {"state.x", "state.v"}) {
    QCustomPlot* p = plotNamed(w, s);
    ASSERT_NE(p, nullptr);
    QCPGraph* ghost = graphNamed(p, QString(s).mid(6) + " [pinned: base]");
    ASSERT_NE(ghost, nullptr) << s;
    EXPECT_GT(ghost->data()->size(), 10u);
  }
}

}  // namespace
}  // namespace kfw
