// The data controller without a window: a CSV of the model's own columns opens and its undo goes
// back to simulated data, a CSV with other column names opens with a mapping that is remembered
// for its header (and forgotten on request), the import dialog is driven through the hook, a
// preset whose data do not read is refused, and the converted data are written elsewhere only.
#include <gtest/gtest.h>

#include <QSettings>
#include <QSignalSpy>
#include <QTemporaryDir>

#include "data/csv.h"
#include "data_controller.h"
#include "document_controller.h"
#include "import_dialog.h"
#include "run_controller.h"

namespace kfw::data_controller_test {
namespace {

// The constant-velocity model loaded, its simulated data written as a CSV with the model's own
// column names and as one with every column but t renamed "log_<name>".
class DataControllerFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    QSettings("kfw", "kfw").remove("columnMaps");
    ASSERT_TRUE(doc.loadPreset("models/cv1d", {}, {"sim.duration=10"}).ok());
    ASSERT_TRUE(runs.waitSettled());
    ASSERT_TRUE(runs.dataset());
    Dataset d = *runs.dataset();
    csv = dir.filePath("own.csv");
    ASSERT_TRUE(write_csv_file(csv.toStdString(), d).ok());
    for (const ColumnSpec& c : doc.scenario()->columns()) {
      if (c.name != "t" && d.has(c.name)) map[c.name] = "log_" + c.name;
    }
    for (auto& n : d.names) {
      if (n != "t") n = "log_" + n;
    }
    renamed = dir.filePath("renamed.csv");
    ASSERT_TRUE(write_csv_file(renamed.toStdString(), d).ok());
    ASSERT_FALSE(map.empty());
  }
  void TearDown() override { QSettings("kfw", "kfw").remove("columnMaps"); }

  QTemporaryDir dir;
  RunController runs;
  DocumentController doc{&runs};
  DataController data{&doc, &runs};
  QString csv, renamed;
  ColumnMap map;  // role -> column of the renamed file
};

TEST_F(DataControllerFiles, OpensACsvAndUndoGoesBackToSimulatedData) {
  QSignalSpy changed(&data, &DataController::dataChanged);
  QSignalSpy opened(&data, &DataController::fileOpened);
  ASSERT_TRUE(data.openDataset(csv).ok());
  ASSERT_TRUE(data.fileData());
  EXPECT_EQ(data.fileData()->source, csv.toStdString());
  EXPECT_EQ(changed.count(), 1);
  EXPECT_EQ(opened.count(), 1);
  EXPECT_TRUE(runs.usesFile());
  ASSERT_TRUE(doc.document()->data());
  EXPECT_EQ(doc.document()->data()->path, csv.toStdString());
  ASSERT_TRUE(runs.waitSettled());
  EXPECT_EQ(runs.dataset()->source, csv.toStdString());  // the run used the file

  ASSERT_TRUE(doc.undo());  // the document's data change, read back by the controller
  EXPECT_FALSE(data.fileData());
  EXPECT_FALSE(runs.usesFile());
  EXPECT_EQ(changed.count(), 2);
  ASSERT_TRUE(doc.redo());
  ASSERT_TRUE(data.fileData());
  EXPECT_EQ(data.fileData()->source, csv.toStdString());
  ASSERT_TRUE(runs.waitSettled());
  data.useSimulatedData();
  EXPECT_FALSE(data.fileData());
  EXPECT_FALSE(doc.document()->data());
  ASSERT_TRUE(runs.waitSettled());
}

TEST_F(DataControllerFiles, AMappedCsvOpensAndItsMappingIsRememberedUntilForgotten) {
  QSignalSpy problem(&data, &DataController::problem);
  EXPECT_FALSE(data.openDataset(renamed).ok());  // unknown header, not interactive
  EXPECT_EQ(problem.count(), 1);
  EXPECT_FALSE(data.fileData());
  ASSERT_TRUE(data.openDatasetMapped(renamed, map).ok());
  ASSERT_TRUE(runs.waitSettled());
  EXPECT_EQ(runs.dataset()->source, renamed.toStdString());
  data.useSimulatedData();
  ASSERT_TRUE(data.openDataset(renamed).ok());  // the same header: the remembered mapping
  ASSERT_TRUE(data.fileData());
  QSignalSpy status(&data, &DataController::status);
  ASSERT_TRUE(data.forgetMapping().ok());
  ASSERT_EQ(status.count(), 1);
  EXPECT_TRUE(status.front().at(0).toString().contains("renamed.csv"));
  data.useSimulatedData();
  EXPECT_FALSE(data.openDataset(renamed).ok());
  ASSERT_TRUE(runs.waitSettled());
}

TEST_F(DataControllerFiles, TheImportDialogAssignsColumnsAndCancelChangesNothing) {
  data.setImportHook([](ImportDialog&) { return false; });  // cancelled
  EXPECT_TRUE(data.openDataset(renamed).ok());
  EXPECT_FALSE(data.fileData());
  data.setImportHook([this](ImportDialog& d) {
    for (const auto& [role, column] : map)
      d.setColumn(role, column);
    EXPECT_EQ(d.problem(), QString());
    return true;
  });
  ASSERT_TRUE(data.openDataset(renamed).ok());
  ASSERT_TRUE(data.fileData());
  EXPECT_EQ(doc.document()->data()->mapping.at(map.begin()->first).column, map.begin()->second);
  ASSERT_TRUE(runs.waitSettled());
}

TEST_F(DataControllerFiles, APresetWhoseDataDoNotReadIsRefused) {
  const Status st = doc.loadPreset("models/cv1d", dir.filePath("missing.csv"));
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("missing.csv"), std::string::npos) << st.error();
  EXPECT_EQ(doc.values().at("sim.duration"), 10.0);  // the open document stays
  ASSERT_TRUE(doc.loadPreset("models/cv1d", csv).ok());
  ASSERT_TRUE(data.fileData());  // read before the document was adopted
  EXPECT_EQ(data.fileData()->source, csv.toStdString());
  ASSERT_TRUE(runs.waitSettled());
}

TEST_F(DataControllerFiles, ConvertedDataAreWrittenOnlyToAnotherFile) {
  EXPECT_FALSE(data.saveConvertedCsv(dir.filePath("out.csv")).ok());  // simulated: nothing
  ASSERT_TRUE(data.openDatasetMapped(renamed, map).ok());
  EXPECT_FALSE(data.saveConvertedCsv(renamed).ok());
  ASSERT_TRUE(data.saveConvertedCsv(dir.filePath("out.csv")).ok());
  auto back = read_csv(dir.filePath("out.csv").toStdString());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->rows(), data.fileData()->rows());
  EXPECT_TRUE(back->has(map.begin()->first));  // in the model's own column names
  ASSERT_TRUE(runs.waitSettled());
}

}  // namespace
}  // namespace kfw::data_controller_test
