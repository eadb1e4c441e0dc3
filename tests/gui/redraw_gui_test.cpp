// What a re-run redraws: the metrics table updates its cells in place (its rows, order and
// highlight stay). (The built-in helicopter view's NIS moving average went with issue 27: the
// preset is a model file; CHANGES.md.)
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QTableWidgetItem>

#include "common/plot_probe.h"
#include "main_window.h"
#include "metrics_panel.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::plotNamed;

class Redraw : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/helicopter.json").ok());
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(w.result());
  }
  MainWindow w;
};

QTableWidgetItem* valueOf(MetricsPanel* m, const QString& key) {
  for (int r = 0; r < m->rowCount(); ++r) {
    const QTableWidgetItem* name = m->item(r, 0);
    if (name && name->data(MetricsPanel::kKeyRole).toString() == key) return m->item(r, 1);
  }
  return nullptr;
}

TEST_F(Redraw, MetricsTableUpdatesItsCellsInPlace) {
  MetricsPanel* m = w.metricsPanel();
  QTableWidgetItem* rmse = valueOf(m, "rmse");
  ASSERT_TRUE(rmse);
  const int rows = m->rowCount();
  const QString before = rmse->text();
  w.setParam("R", 50.0);
  ASSERT_TRUE(w.waitForRun());
  // The same cell object, now holding the new run's value.
  EXPECT_EQ(valueOf(m, "rmse"), rmse);
  EXPECT_EQ(m->rowCount(), rows);
  const double now = w.result()->metrics.at("rmse");
  EXPECT_EQ(rmse->text(), MetricsPanel::format(now));
  EXPECT_EQ(rmse->data(MetricsPanel::kValueRole).toDouble(), now);
  EXPECT_NE(rmse->text(), before);
  EXPECT_TRUE(m->item(0, 0)->data(MetricsPanel::kPrimaryRole).toBool());
  // Every value cell is the run's metric, or a dash with the reason for an undefined one.
  for (int r = 0; r < m->rowCount(); ++r) {
    const QTableWidgetItem* name = m->item(r, 0);
    if (!name || !name->data(MetricsPanel::kKeyRole).isValid()) continue;
    const std::string key = name->data(MetricsPanel::kKeyRole).toString().toStdString();
    const auto it = w.result()->metrics.find(key);
    if (it == w.result()->metrics.end()) {
      EXPECT_EQ(m->item(r, 1)->text(), "—") << key;
    } else {
      EXPECT_EQ(m->item(r, 1)->text(), MetricsPanel::format(it->second)) << key;
    }
  }
}

}  // namespace
}  // namespace kfw
