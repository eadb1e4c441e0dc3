// The import dialog's file format (issue 13), offscreen: the separator and header-row choices
// re-read the file and the preview at once, show what was detected, and are kept in the mapping
// (so Data ▸ Mapping… and a reload read the file the same way); a file without a header opens
// with columns named by position and matches the kfw file's run; a text cell in it is named by
// FILE:LINE:COL and the previous dataset stays.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QComboBox>
#include <QLabel>
#include <QPushButton>
#include <QSettings>
#include <QTableWidget>
#include <QTemporaryDir>
#include <cstdlib>
#include <fstream>

#include "common/import_files.h"
#include "document/session.h"
#include "gui/import_window.h"
#include "import_dialog.h"
#include "main_window.h"

namespace kfw {
namespace {

class ImportFormatGui : public testing::ImportWindow {
 protected:
  ImportFormatGui() : ImportWindow(3000) {}
  void SetUp() override {
    ImportWindow::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    // The reference file without its header row.
    std::ifstream in(files.reference);
    std::string line, body;
    std::getline(in, line);
    while (std::getline(in, line))
      body += line + "\n";
    nohead = dir.filePath("nohead.csv").toStdString();
    std::ofstream(nohead) << body;
  }

  static QComboBox* combo(ImportDialog& d, const char* name) {
    auto* c = d.findChild<QComboBox*>(name);
    EXPECT_NE(c, nullptr) << name;
    return c;
  }

  std::string nohead;
};

TEST_F(ImportFormatGui, TheSeparatorChoiceRereadsThePreviewAndIsKept) {
  const Metrics want = open(files.reference, [](ImportDialog&) {});
  const Metrics tabs = open(files.tabs, [&](ImportDialog& d) {
    QComboBox* sep = combo(d, "importSeparator");
    ASSERT_NE(sep, nullptr);
    EXPECT_EQ(sep->itemText(0), "detected: tab");
    EXPECT_EQ(d.preview()->columnCount(), 4);
    // Comma: the file is read again at once, one column; the roles lose their columns.
    d.setSeparator(',');
    EXPECT_EQ(d.table().separator, ',');
    EXPECT_EQ(d.table().columns(), 1u);
    EXPECT_EQ(d.preview()->columnCount(), 1);
    EXPECT_NE(d.findChild<QLabel*>("importInfo")->text().indexOf("comma-separated"), -1);
    EXPECT_FALSE(d.okButton()->isEnabled());
    EXPECT_NE(d.problem().indexOf("(required)"), -1) << d.problem().toStdString();
    // Tab, chosen: the columns come back, the roles with them (the guess on the new reading).
    d.setSeparator('\t');
    EXPECT_EQ(d.preview()->columnCount(), 4);
    EXPECT_EQ(d.preview()->horizontalHeaderItem(1)->text(), "gyro_dps");
    EXPECT_EQ(d.mapping().at("gyro").column, "gyro_dps");
    EXPECT_EQ(d.mapping().separator, '\t');
    EXPECT_EQ(sep->itemText(0), "detected");  // the detected entry no longer names one
    // KFW_TEST_SHOT_DIR=DIR keeps a picture of the dialog for a human to look at.
    if (const char* shots = std::getenv("KFW_TEST_SHOT_DIR")) {
      d.resize(900, 640);
      d.grab().save(QString(shots) + "/import_dialog_separator.png");
    }
  });
  expect_same(tabs, want, "tabs, separator chosen");
  // Kept in the mapping: the document, the session, and Data ▸ Mapping… start from it.
  EXPECT_EQ(w.document()->data()->mapping.separator, '\t');
  auto back = parse_session(session_to_json(w.document()->to_session()), "s.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->mapping.separator, '\t');
  char shown = 0;
  w.setImportHook([&](ImportDialog& d) {
    shown = static_cast<char>(combo(d, "importSeparator")->currentData().toInt());
    return false;  // cancelled: nothing changes
  });
  ASSERT_TRUE(w.editMapping().ok());
  EXPECT_EQ(shown, '\t');
}

TEST_F(ImportFormatGui, AHeaderlessFileOpensByColumnPosition) {
  const Metrics want = open(files.reference, [](ImportDialog&) {});
  const Metrics got = open(nohead, [&](ImportDialog& d) {
    EXPECT_FALSE(d.table().has_header());
    EXPECT_NE(d.findChild<QLabel*>("importInfo")->text().indexOf("no header"), -1);
    QComboBox* header = combo(d, "importHeader");
    ASSERT_NE(header, nullptr);
    EXPECT_EQ(header->itemText(0), "detected: none (col1, col2, …)");
    EXPECT_EQ(d.preview()->horizontalHeaderItem(0)->text(), "col1");
    EXPECT_EQ(d.preview()->rowCount(), 20);
    EXPECT_EQ(d.mapping().at("t").column, "col1");  // the increasing first column
    // Forced to a header: this first row (0,0,...) has a repeated name, which the dialog shows
    // and refuses OK for; back to detected, the file reads again.
    d.setHeader(HeaderRow::first);
    EXPECT_NE(d.problem().indexOf(":1:3: duplicate column '0'"), -1) << d.problem().toStdString();
    EXPECT_FALSE(d.okButton()->isEnabled());
    d.setHeader(HeaderRow::detect);
    EXPECT_EQ(d.problem(), "choose a column for 'gyro' (required)");
    EXPECT_FALSE(d.table().has_header());
    d.setColumn("gyro", "col2");
    d.setColumn("angle", "col3");
    d.setColumn("truth", "col4");
  });
  expect_same(got, want, "no header");
  EXPECT_EQ(w.dataset()->rows(), files.rows);
}

TEST_F(ImportFormatGui, ATextCellInAHeaderlessFileIsNamedAndTheDatasetStays) {
  const std::string before = w.dataset()->source;
  const std::string bad = dir.filePath("bad.csv").toStdString();
  std::ofstream(bad) << "0,1,2,2\n0.01,1,2,2\n0.02,1,x,2\n0.03,1,2,2\n";
  QString shown;
  w.setImportHook([&](ImportDialog& d) {
    d.setColumn("gyro", "col2");
    d.setColumn("angle", "col3");
    shown = d.problem();
    EXPECT_FALSE(d.okButton()->isEnabled());
    return true;  // refused
  });
  EXPECT_TRUE(w.openDataset(QString::fromStdString(bad)).ok());
  EXPECT_TRUE(shown.startsWith(QString::fromStdString(bad) + ":3:8: ")) << shown.toStdString();
  EXPECT_NE(shown.indexOf("'x' is not a number"), -1) << shown.toStdString();
  EXPECT_EQ(w.dataset()->source, before);
}

}  // namespace
}  // namespace kfw
