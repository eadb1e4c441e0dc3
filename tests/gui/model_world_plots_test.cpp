// Issue 27 (model files, part 2) in the window: a channel of two components gets its whiteness
// per component in the Consistency tab.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QFile>
#include <QTemporaryDir>
#include <cmath>
#include <numbers>

#include "common/plot_probe.h"
#include "consistency_panel.h"
#include "main_window.h"
#include "transport_bar.h"

namespace kfw {
namespace model_world_plots_gui_test {
namespace {

using testing::graphNamed;
using testing::plotNamed;

QString modelPreset(const char* name) {
  return QString(KFW_SOURCE_DIR) + "/presets/models/" + name + ".json";
}

TEST(ModelWorldPlots, AVectorChannelShowsItsComponentsWhiteness) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("range_bearing")).ok());
  ASSERT_TRUE(w.waitForRun(60000));
  w.consistency()->refresh();
  const QString text = w.consistency()->summary();
  EXPECT_TRUE(text.contains("Ljung–Box p per component: range")) << text.toStdString();
  EXPECT_TRUE(text.contains("bearing")) << text.toStdString();
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->filter("_consistency_whiteness.radar").size(), 1);
}

}  // namespace
}  // namespace model_world_plots_gui_test
}  // namespace kfw
