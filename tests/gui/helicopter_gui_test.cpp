// The helicopter window driven as a user would, offscreen: sliders change what the plots hold,
// the operating point moves, export writes real images, a bad CSV keeps the old data. Since issue
// 27 presets/helicopter.json is a model file: the generic model view's plots.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <algorithm>

#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QImage>
#include <QLabel>
#include <QSlider>
#include <QTemporaryDir>
#include <QTextStream>

#include "common/plot_probe.h"
#include "main_window.h"
#include "param_panel.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::graphValues;
using testing::plotNamed;

class HelicopterWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/helicopter.json").ok());
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(w.result());
  }
  MainWindow w;
};

TEST_F(HelicopterWindow, PanelIsGeneratedFromTheTable) {
  for (const char* key : {"Q", "R", "m", "gamma", "sim.sigma_gyro"}) {
    EXPECT_NE(w.findChild<QSlider*>(QString("slider.") + key), nullptr) << key;
  }
  // Log slider spans decades: its ends are the table's 1e-6 … 1e6.
  const ParamSpec s{"Q", "", "", 1e-6, 1e6, 1, Scale::kLog};
  EXPECT_NEAR(ParamPanel::fromSlider(s, 1e-6, 1e6, 0), 1e-6, 1e-18);
  EXPECT_NEAR(ParamPanel::fromSlider(s, 1e-6, 1e6, ParamPanel::kSliderSteps), 1e6, 1e-6);
  EXPECT_NEAR(ParamPanel::fromSlider(s, 1e-6, 1e6, ParamPanel::kSliderSteps / 2), 1.0, 1e-12);
}

TEST_F(HelicopterWindow, MovingTheRSliderChangesEstimateAndOperatingPoint) {
  QCustomPlot* angle = plotNamed(w, "state.theta");
  QCustomPlot* curve = plotNamed(w, "gain_curve");
  ASSERT_TRUE(angle && curve);
  QCPGraph* est = graphNamed(angle, "estimate of theta");
  QCPGraph* op = graphNamed(curve, "operating point");
  ASSERT_TRUE(est && op);
  // Replay cursor at step 1999: below the decimation threshold, the plot holds every step.
  w.transport()->seek(1999);
  const auto before = graphValues(est);
  // One point per gain entry at the parameter's value: k1 (K.theta.angle) and k2 (0 for γ = 0).
  const auto k1_at = [&op] {
    double k = -1;
    for (auto it = op->data()->constBegin(); it != op->data()->constEnd(); ++it)
      k = std::max(k, it->value);
    return k;
  };
  ASSERT_EQ(op->data()->size(), 2);
  const double beta0 = op->data()->constBegin()->key, k0 = k1_at();
  ASSERT_EQ(before.size(), 2000u);

  auto* slider = w.findChild<QSlider*>("slider.R");
  ASSERT_NE(slider, nullptr);
  slider->setValue(slider->value() + 500);  // R up by 1.5 decades (3 decades over 1000 steps)
  ASSERT_TRUE(w.waitForRun());
  EXPECT_GT(w.values().at("R"), 1.96 * 20);
  const auto after = graphValues(est);
  ASSERT_EQ(after.size(), before.size());
  double diff = 0;
  for (std::size_t i = 0; i < after.size(); ++i)
    diff = std::max(diff, std::abs(after[i] - before[i]));
  EXPECT_GT(diff, 0.1);
  // The curve runs along Q: the operating point keeps its abscissa, its gain falls with N_θ up.
  op = graphNamed(curve, "operating point");  // the curve's graphs are redrawn with the run
  ASSERT_TRUE(op);
  ASSERT_EQ(op->data()->size(), 2);
  const double q1 = op->data()->constBegin()->key, k1 = k1_at();
  EXPECT_DOUBLE_EQ(q1, beta0);
  EXPECT_DOUBLE_EQ(q1, w.values().at("Q"));
  EXPECT_LT(k1, k0);
}

TEST_F(HelicopterWindow, SimulatorSliderResimulates) {
  QCPGraph* sensor = graphNamed(plotNamed(w, "measured.angle.angle"), "measured angle");
  ASSERT_NE(sensor, nullptr);
  const auto before = graphValues(sensor);
  w.setParam("sim.seed", 7);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_NE(graphValues(sensor), before);
}

TEST_F(HelicopterWindow, ReplayRevealsUpToTheCursor) {
  QCPGraph* est = graphNamed(plotNamed(w, "state.theta"), "estimate of theta");
  ASSERT_NE(est, nullptr);
  const std::size_t all = w.result()->steps();
  w.transport()->seek(99);
  EXPECT_EQ(est->data()->size(), 100);
  EXPECT_DOUBLE_EQ((est->data()->constEnd() - 1)->key, w.result()->t[99]);
  w.transport()->setShowAll(true);
  // Everything is shown, reduced to what the raster can show (first/min/max/last per column).
  EXPECT_DOUBLE_EQ((est->data()->constEnd() - 1)->key, w.result()->t.back());
  EXPECT_GT(static_cast<std::size_t>(est->data()->size()), 1000u);
  EXPECT_LE(static_cast<std::size_t>(est->data()->size()), all);
}

TEST_F(HelicopterWindow, ExportWritesNonBlankFiles) {
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png", "pdf", "svg"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), 3 * w.exportedPlots().size());
  for (const QString& f : *files) {
    EXPECT_GT(QFile(f).size(), 2000) << f.toStdString();
    if (!f.endsWith(".png")) continue;
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    EXPECT_EQ(img.width(), 1200);
    const int colored = testing::colouredPixels(f);
    EXPECT_GT(colored, 200) << "no coloured curves in " << f.toStdString();
  }
}

TEST_F(HelicopterWindow, MalformedCsvShowsErrorAndKeepsData) {
  const auto before = w.result();
  const auto data_before = w.dataset();
  QTemporaryDir dir;
  const QString bad = dir.filePath("bad.csv");
  {
    QFile f(bad);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    QTextStream(&f) << "t,gyro,angle\n0,1,2\n0.02,abc,3\n";
  }
  auto st = w.openDataset(bad);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("bad.csv:3:6: column 'gyro': 'abc' is not a number"), std::string::npos)
      << st.error();
  auto* banner = w.findChild<QLabel*>("errorBanner");
  ASSERT_NE(banner, nullptr);
  EXPECT_FALSE(banner->isHidden());
  EXPECT_TRUE(banner->text().contains("bad.csv:3"));
  EXPECT_TRUE(w.waitForRun());
  EXPECT_EQ(w.result(), before);
  EXPECT_EQ(w.dataset(), data_before);

  const QString missing = dir.filePath("missing.csv");
  {
    QFile f(missing);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    QTextStream(&f) << "t,gyro\n0,1\n0.02,2\n";
  }
  auto st2 = w.openDataset(missing);
  ASSERT_FALSE(st2.ok());
  EXPECT_NE(st2.error().find("missing required column 'angle'"), std::string::npos);
}

TEST_F(HelicopterWindow, GoodCsvReplacesDataAndDisablesSimulator) {
  auto st = w.openDataset(QString(KFW_SOURCE_DIR) + "/data/helicopter.csv");
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.dataset()->source, std::string(KFW_SOURCE_DIR) + "/data/helicopter.csv");
  auto* sim = w.findChild<QSlider*>("slider.sim.seed");
  ASSERT_NE(sim, nullptr);
  EXPECT_FALSE(sim->isEnabled());
  w.useSimulatedData();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(sim->isEnabled());
}

TEST(HelicopterWindowLoad, BadPresetChangesNothing) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter").ok());
  ASSERT_TRUE(w.waitForRun());
  const auto r = w.result();
  QTemporaryDir dir;
  QFile f(dir.filePath("p.json"));
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(
      "{\"format\": \"kfw-preset\", \"version\": 1, \"scenario\": \"helicopter\", "
      "\"parameters\": {\"R\": {\"value\": 0}}}");
  f.close();
  auto st = w.loadPreset(f.fileName());
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("'R' = 0 is out of range"), std::string::npos) << st.error();
  EXPECT_EQ(w.result(), r);
  EXPECT_EQ(w.values().at("R"), 1.96);
}

}  // namespace
}  // namespace kfw
