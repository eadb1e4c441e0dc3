// Every shipped preset, in the real window offscreen: it runs, every exported plot has coloured
// content, the consistency panel has its channels, and a filter slider changes the result.
#include <gtest/gtest.h>

#include <QDir>
#include <QFile>
#include <QImage>
#include <QTemporaryDir>

#include "common/plot_probe.h"
#include "consistency_panel.h"
#include "main_window.h"
#include "param_panel.h"

namespace kfw {
namespace {

class AllPresets : public ::testing::TestWithParam<const char*> {};

TEST_P(AllPresets, RunsExportsAndReportsConsistency) {
  const QString preset = QString(KFW_SOURCE_DIR) + "/presets/" + GetParam() + ".json";
  MainWindow w;
  auto st = w.loadPreset(preset);
  if (!st && st.error().find("shared/data") != std::string::npos) GTEST_SKIP() << st.error();
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  ASSERT_TRUE(w.result()) << w.lastError().toStdString();
  EXPECT_FALSE(w.result()->channels().empty()) << GetParam();
  EXPECT_TRUE(w.result()->metrics.count("nis_mean")) << GetParam();
  EXPECT_TRUE(w.result()->metrics.count("whiteness_p")) << GetParam();

  w.consistency()->refresh();
  EXPECT_TRUE(w.consistency()->summary().contains("Ljung–Box"))
      << w.consistency()->summary().toStdString();

  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  for (const QString& f : *files) {
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    const int colored = testing::colouredPixels(f);
    EXPECT_GT(colored, 40) << "no coloured content in " << f.toStdString();
  }

  // The main filter parameter moved changes the metrics.
  const auto before = w.result()->metrics;
  const std::string key = w.primaryParameter();
  const ParamSpec* spec = w.scenario()->params().find(key);
  ASSERT_NE(spec, nullptr);
  const double v = w.values().at(key);
  w.setParam(key, v * 3.0 <= spec->max ? v * 3.0 : v / 3.0);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_NE(w.result()->metrics.at("nis_mean"), before.at("nis_mean")) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Presets, AllPresets,
                         ::testing::Values("helicopter", "broad_imu", "radome", "ballbeam",
                                           "underwater"));

}  // namespace
}  // namespace kfw
