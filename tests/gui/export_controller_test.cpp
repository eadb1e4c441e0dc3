// The export controller without a window: the model's plots and the consistency panel's, named
// after the preset, written in every format asked for; a chosen subset; an unknown plot name
// refused; nothing to export before a run, with the last problem named.
#include <gtest/gtest.h>

#include <QDir>
#include <QFileInfo>
#include <QGridLayout>
#include <QTemporaryDir>

#include "consistency_panel.h"
#include "document_controller.h"
#include "export_controller.h"
#include "run_controller.h"

namespace kfw::export_controller_test {
namespace {

// The constant-velocity model run once, its plots drawn in a widget, its consistency panel set.
class ExportPlots : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(doc.loadPreset("models/cv1d", {}, {"sim.duration=10"}).ok());
    ASSERT_TRUE(runs.waitSettled());
    ASSERT_TRUE(runs.result());
    view = views().make(doc.scenario()->name());
    ASSERT_TRUE(view);
    view->setScenario(doc.scenario());
    auto* grid = new QGridLayout(&host);
    plots = view->createPlots(&host);
    for (int i = 0; i < plots.size(); ++i)
      grid->addWidget(plots[i].plot, i / 2, i % 2);
    view->setDataset(runs.dataset());
    view->setResult(runs.result(), doc.values());
    consistency.setResult(runs.result());
    exporter.setPlots(plots, "cv1d");
  }

  RunController runs;
  DocumentController doc{&runs};
  QWidget host;
  ConsistencyPanel consistency;
  ExportController exporter{&runs, &consistency};
  std::unique_ptr<ScenarioView> view;
  QList<PlotPanel> plots;
  QTemporaryDir dir;
};

TEST_F(ExportPlots, EveryPlotIsWrittenInEveryFormatNamedAfterThePreset) {
  const QStringList names = exporter.plotNames();
  ASSERT_GT(names.size(), plots.size());  // the consistency panel's follow the view's
  for (int i = 0; i < plots.size(); ++i)
    EXPECT_EQ(names[i], plots[i].name);
  EXPECT_TRUE(names.filter("consistency_nis").size() > 0);
  auto files = exporter.exportAll(dir.path(), {"png", "svg"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), 2 * names.size());
  for (const QString& f : *files) {
    EXPECT_TRUE(QFileInfo(f).fileName().startsWith("cv1d_")) << f.toStdString();
    EXPECT_GT(QFileInfo(f).size(), 0) << f.toStdString();
  }
  EXPECT_TRUE(QFileInfo::exists(dir.filePath("cv1d_" + plots.front().name + ".png")));
}

TEST_F(ExportPlots, AChosenPlotAloneAndAnUnknownNameRefused) {
  auto one = exporter.exportAll(dir.filePath("one"), {"svg"}, {}, {plots.front().name});
  ASSERT_TRUE(one.ok()) << one.error();
  ASSERT_EQ(one->size(), 1);
  EXPECT_EQ(QDir(dir.filePath("one")).entryList(QDir::Files).size(), 1);
  auto bad = exporter.exportAll(dir.filePath("bad"), {"svg"}, {}, {"no_such_plot"});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.exit_code(), kExitInvalid);
  EXPECT_FALSE(QFileInfo::exists(dir.filePath("bad/cv1d_no_such_plot.svg")));
}

TEST(ExportController, NothingToExportBeforeARunNamesTheLastProblem) {
  RunController runs;
  ExportController exporter(&runs, nullptr);
  EXPECT_TRUE(exporter.plotNames().isEmpty());
  exporter.noteProblem("data: no such file");
  QTemporaryDir dir;
  auto r = exporter.exportAll(dir.path(), {"png"});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "export: no result to plot (data: no such file)");
  EXPECT_EQ(r.exit_code(), kExitFailed);
}

}  // namespace
}  // namespace kfw::export_controller_test
