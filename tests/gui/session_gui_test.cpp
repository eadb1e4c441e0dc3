// Snapshots, column mapping and sessions, driven offscreen.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QFile>
#include <QJsonObject>
#include <QSettings>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTextStream>

#include "common/plot_probe.h"
#include "core/dataset.h"
#include "data/csv.h"
#include "main_window.h"
#include "metrics_panel.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::graphValues;
using testing::plotNamed;

TEST(Snapshots, GhostAndMetricsColumnFollowThePinnedTuning) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=30"}).ok());
  ASSERT_TRUE(w.waitForRun());
  const double rmse_pinned = w.result()->metrics.at("rmse");
  w.pinSnapshot("loose");
  w.setParam("R", 100.0);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.snapshotCount(), 1);
  QCPGraph* ghost = graphNamed(plotNamed(w, "state.theta"), "theta [pinned: loose]");
  ASSERT_NE(ghost, nullptr);
  EXPECT_GT(ghost->data()->size(), 100);
  auto* table = w.findChild<QTableWidget*>("metrics");
  ASSERT_EQ(table->columnCount(), 3);
  EXPECT_EQ(table->horizontalHeaderItem(2)->text(), "loose");
  for (int r = 0; r < table->rowCount(); ++r) {
    if (table->item(r, 0)->data(Qt::UserRole).toString() != "rmse") continue;
    EXPECT_NEAR(table->item(r, 2)->data(MetricsPanel::kValueRole).toDouble(), rmse_pinned,
                1e-12 * rmse_pinned);
    EXPECT_NEAR(table->item(r, 2)->text().toDouble(), rmse_pinned, 1e-3 * rmse_pinned);
    EXPECT_NE(table->item(r, 1)->text(), table->item(r, 2)->text());
  }
  w.clearSnapshots();
  EXPECT_EQ(graphNamed(plotNamed(w, "state.theta"), "theta [pinned: loose]"), nullptr);
  EXPECT_EQ(table->columnCount(), 2);
}

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    // A log with other column names: the helicopter data renamed.
    auto d = read_csv(std::string(KFW_SOURCE_DIR) + "/data/helicopter.csv");
    ASSERT_TRUE(d.ok());
    for (auto& name : d->names) {
      if (name == "gyro") name = "gx";
      if (name == "angle") name = "acc_roll";
      if (name == "truth") name = "mocap";
    }
    csv = dir.filePath("renamed.csv");
    ASSERT_TRUE(write_csv_file(csv.toStdString(), *d).ok());
    QSettings("kfw", "kfw").remove("columnMaps");
  }
  QTemporaryDir dir;
  QString csv;
};

TEST_F(Files, ColumnMappingIsAppliedAndRemembered) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter").ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_FALSE(w.openDataset(csv).ok());  // unknown header, not interactive: a clear error
  ASSERT_TRUE(
      w.openDatasetMapped(csv, {{"gyro", "gx"}, {"angle", "acc_roll"}, {"truth", "mocap"}}).ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_LT(w.result()->metrics.at("rmse"), 1.0);
  w.useSimulatedData();
  ASSERT_TRUE(w.waitForRun());
  // Same header again: the remembered mapping applies without asking.
  ASSERT_TRUE(w.openDataset(csv).ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.dataset()->source, csv.toStdString());
}

TEST_F(Files, SessionRestoresValuesDataMappingAndSnapshots) {
  const QString session = dir.filePath("s.json");
  {
    MainWindow w;
    ASSERT_TRUE(w.loadPreset("helicopter").ok());
    ASSERT_TRUE(
        w.openDatasetMapped(csv, {{"gyro", "gx"}, {"angle", "acc_roll"}, {"truth", "mocap"}}).ok());
    ASSERT_TRUE(w.waitForRun());
    w.pinSnapshot("base");
    w.setParam("Q", 10.0);
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(w.saveSession(session).ok());
  }
  MainWindow w;
  ASSERT_TRUE(w.loadSession(session).ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("Q"), 10.0);
  EXPECT_EQ(w.dataset()->source, csv.toStdString());
  EXPECT_EQ(w.snapshotCount(), 1);
  EXPECT_NE(graphNamed(plotNamed(w, "state.theta"), "theta [pinned: base]"), nullptr);

  QFile bad(dir.filePath("bad.json"));
  ASSERT_TRUE(bad.open(QIODevice::WriteOnly));
  bad.write(
      "{\"format\": \"kfw-session\", \"version\": 1, \"preset\": \"helicopter\", "
      "\"scenario\": \"helicopter\", \"values\": {\"R\": -5}}");
  bad.close();
  auto st = w.loadSession(bad.fileName());
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("'R' = -5 is out of range"), std::string::npos) << st.error();
  EXPECT_EQ(w.values().at("Q"), 10.0);  // nothing lost
}

TEST(ViewState, RegisteredPartsRoundTripThroughASession) {
  QTemporaryDir dir;
  const QString path = dir.filePath("view.kfw.json");
  QJsonValue restored;
  {
    MainWindow w;
    w.addViewStatePart(
        "probe",
        [] {
          return QJsonValue(QJsonObject{{"x0", 1.5}});
        },
        [](const QJsonValue&) {});
    ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=10"}).ok());
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(w.saveSession(path).ok());
  }
  MainWindow w;
  w.addViewStatePart(
      "probe", [] { return QJsonValue(); }, [&](const QJsonValue& v) { restored = v; });
  ASSERT_TRUE(w.loadSession(path).ok());
  EXPECT_DOUBLE_EQ(restored.toObject()["x0"].toDouble(), 1.5);
  // The older ':'-separated form (geometry, splitters) is still read, without parts.
  restored = QJsonValue();
  w.restoreViewState(QString::fromLatin1(w.saveGeometry().toBase64()) + ":");
  EXPECT_TRUE(restored.isUndefined() || restored.isNull());
}

}  // namespace
}  // namespace kfw
