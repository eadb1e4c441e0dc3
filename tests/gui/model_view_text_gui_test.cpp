// The generic model view's words (issue 32, item 14): a state plot names truth only when the run
// has it, and presentation opens on the plots that show a tuning (the innovation and the NIS)
// unless the model file puts its own panels first.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QApplication>
#include <QFile>
#include <QTemporaryDir>
#include <QTextStream>

#include "common/plot_probe.h"
#include "main_window.h"

namespace kfw {
namespace {

QString titleOf(const QCustomPlot* p) {
  const auto* t = p->findChild<QCPTextElement*>("title");
  return t ? QString(t->text()).replace('\n', ' ') : QString();
}

TEST(ModelViewText, AStateWithoutTruthIsNotTitledTruth) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  // cv1d's columns less the velocity's truth.
  const QString csv = dir.filePath("no_v_truth.csv");
  {
    QFile f(csv);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly | QIODevice::Text));
    QTextStream out(&f);
    out << "t,z,x_true\n";
    for (int k = 0; k < 200; ++k)
      out << k * 0.1 << ',' << 0.5 * k * 0.1 + 0.1 * ((k * 7) % 5 - 2) << ',' << 0.05 * k << '\n';
  }
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/cv1d", csv).ok());
  ASSERT_TRUE(w.waitForRun());
  QApplication::processEvents();
  const QCustomPlot* x = testing::plotNamed(w, "state.x");
  const QCustomPlot* v = testing::plotNamed(w, "state.v");
  ASSERT_TRUE(x && v);
  EXPECT_TRUE(titleOf(x).contains("truth and estimate")) << titleOf(x).toStdString();
  EXPECT_FALSE(titleOf(v).contains("truth")) << titleOf(v).toStdString();
  EXPECT_TRUE(titleOf(v).contains("estimate ± 2σ")) << titleOf(v).toStdString();
  // Back to simulated data: both have truth again.
  w.useSimulatedData();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(titleOf(v).contains("truth and estimate")) << titleOf(v).toStdString();
}

TEST(ModelViewText, PresentationOpensOnTheInnovationAndTheNis) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/cv2d").ok());
  ASSERT_TRUE(w.waitForRun());
  const QStringList shown = w.presentedPlots();
  ASSERT_EQ(shown.size(), 2);
  EXPECT_TRUE(shown[0].startsWith("innovation.")) << shown[0].toStdString();
  EXPECT_TRUE(shown[1].startsWith("nis.")) << shown[1].toStdString();
  // A file that puts its own panels first keeps them.
  MainWindow radome;
  ASSERT_TRUE(radome.loadPreset("radome").ok());
  ASSERT_TRUE(radome.waitForRun(60000));
  EXPECT_EQ(radome.presentedPlots(), (QStringList{radome.plots()[0].name, radome.plots()[1].name}));
}

// A choice of presented plots belongs to its preset: another model file keeps its own default.
TEST(ModelViewText, PresentedPlotsAreRememberedPerPreset) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/cv1d").ok());
  ASSERT_TRUE(w.waitForRun());
  w.setPresentedPlots({"state.v"});
  ASSERT_TRUE(w.loadPreset("models/cv2d").ok());
  ASSERT_TRUE(w.waitForRun());
  ASSERT_FALSE(w.presentedPlots().isEmpty());
  EXPECT_TRUE(w.presentedPlots()[0].startsWith("innovation."))
      << w.presentedPlots()[0].toStdString();
  ASSERT_TRUE(w.loadPreset("models/cv1d").ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.presentedPlots(), QStringList{"state.v"});
}

}  // namespace
}  // namespace kfw
