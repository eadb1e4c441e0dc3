// The window drives the shared document: every parameter change is an undo step, undo/redo
// restore the values and the plots, data changes and snapshot deletion are undoable, and the
// metrics table shows each metric's label, unit and description.
#include <gtest/gtest.h>
#include <qcustomplot.h>

#include <QAction>
#include <QTableWidget>

#include "common/plot_probe.h"
#include "main_window.h"
#include "metrics_panel.h"
#include "param_panel.h"

namespace kfw {
namespace {

using testing::plotNamed;

std::vector<double> lastGraph(MainWindow& w, const QString& plot) {
  std::vector<double> y;
  QCustomPlot* p = plotNamed(w, plot);
  if (!p || p->graphCount() == 0) return y;
  for (auto it = p->graph(0)->data()->constBegin(); it != p->graph(0)->data()->constEnd(); ++it)
    y.push_back(it->value);
  return y;
}

TEST(DocumentGui, UndoRedoRestoresEveryParameterAndThePlots) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const ParamValues start = w.values();
  const auto plot_start = lastGraph(w, "innovation");
  w.setParam("R", 50.0);
  ASSERT_TRUE(w.waitForRun());
  w.applyValues({{"Q", 5.0}, {"gamma", 0.01}});
  ASSERT_TRUE(w.waitForRun());
  const ParamValues tuned = w.values();
  EXPECT_NE(tuned, start);
  auto* undo = w.findChild<QAction*>("undoAction");
  ASSERT_NE(undo, nullptr);
  EXPECT_TRUE(undo->isEnabled());
  undo->trigger();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("Q"), start.at("Q"));
  EXPECT_EQ(w.values().at("R"), 50.0);
  ASSERT_TRUE(w.undo());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values(), start);
  EXPECT_EQ(w.paramPanel()->values(), start);  // the controls show it too
  EXPECT_EQ(lastGraph(w, "innovation"), plot_start);
  EXPECT_FALSE(w.undo());
  ASSERT_TRUE(w.redo());
  ASSERT_TRUE(w.redo());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values(), tuned);
}

TEST(DocumentGui, SnapshotDeletionAndDataAreUndoable) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  w.pinSnapshot("a");
  w.clearSnapshots();
  EXPECT_EQ(w.snapshotCount(), 0);
  ASSERT_TRUE(w.undo());
  EXPECT_EQ(w.snapshotCount(), 1);
  ASSERT_TRUE(w.openDataset(QString(KFW_SOURCE_DIR) + "/data/helicopter.csv").ok());
  ASSERT_TRUE(w.waitForRun());
  ASSERT_TRUE(w.document()->data().has_value());
  ASSERT_TRUE(w.undo());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_FALSE(w.document()->data().has_value());
  EXPECT_EQ(w.dataset()->source.rfind("simulated", 0), 0u) << w.dataset()->source;
}

TEST(DocumentGui, MetricsTableShowsLabelUnitAndDescription) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun());
  auto* table = w.findChild<QTableWidget*>("metrics");
  ASSERT_NE(table, nullptr);
  bool saw_rmse = false;
  for (int r = 0; r < table->rowCount(); ++r) {
    if (table->item(r, 0)->data(MetricsPanel::kGroupRole).isValid()) continue;  // a group header
    const QString key = table->item(r, 0)->data(Qt::UserRole).toString();
    EXPECT_FALSE(key.isEmpty());
    EXPECT_FALSE(table->item(r, 0)->toolTip().isEmpty()) << key.toStdString();
    if (key == "rmse") {
      saw_rmse = true;
      EXPECT_EQ(r, 0) << "the primary accuracy metric comes first";
      EXPECT_TRUE(table->item(r, 0)->text().contains("(angle, deg)"))
          << table->item(r, 0)->text().toStdString();
      EXPECT_TRUE(table->item(r, 0)->toolTip().contains("root-mean-square"));
    }
  }
  EXPECT_TRUE(saw_rmse);
}

}  // namespace
}  // namespace kfw
