// The consistency panel, the same for every scenario: it reads the run's channels.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QFile>
#include <QTabWidget>
#include <QTemporaryDir>

#include "consistency_panel.h"
#include "core/statistics.h"
#include "main_window.h"

namespace kfw {
namespace {

TEST(ConsistencyPanel, ShowsNisWhitenessAndNeesOfTheRun) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter").ok());
  ASSERT_TRUE(w.waitForRun());
  ConsistencyPanel* c = w.consistency();
  c->refresh();
  const auto plots = c->plots();
  ASSERT_EQ(plots.size(), 3);
  auto* nis = plots[0].plot;
  // Every update is shown (dense scatters keep one dot per 2×2-pixel cell).
  const auto updates = count_finite(w.result()->channels()[0].nis);
  EXPECT_LE(static_cast<std::size_t>(nis->graph(0)->data()->size()), updates);
  EXPECT_GT(static_cast<std::size_t>(nis->graph(0)->data()->size()), updates / 3);
  EXPECT_TRUE(c->summary().contains("Ljung–Box p")) << c->summary().toStdString();
  EXPECT_TRUE(c->summary().contains("NEES")) << c->summary().toStdString();
  // A window change redraws the moving average with the bounds of that window.
  const double hi50 = plots[0].plot->graph(5)->data()->constBegin()->value;
  c->setWindow(500);
  const double hi500 = plots[0].plot->graph(5)->data()->constBegin()->value;
  EXPECT_LT(hi500, hi50);
  // Exported with the scenario's plots.
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok());
  EXPECT_TRUE(files->contains(dir.filePath("helicopter_consistency_whiteness.angle.png")));
}

// (Radome had four channels until its preset became a model file with one 3-D channel, issue 28;
// underwater's five channels take its place.)
TEST(ConsistencyPanel, UnderwaterHasFiveChannels) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("underwater").ok());
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_EQ(w.result()->channels().size(), 5u);
  w.consistency()->setChannel(1);
  w.consistency()->refresh();
  EXPECT_TRUE(w.consistency()->summary().contains("Ljung–Box"))
      << w.consistency()->summary().toStdString();
}

}  // namespace
}  // namespace kfw
