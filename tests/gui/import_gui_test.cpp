// The import dialog and the Data menu/tab (issue 13), driven offscreen: the four foreign layouts
// opened through the dialog match the kfw file's run; OK is refused while a required role is
// unassigned or a column is assigned twice; bad files leave the previous dataset loaded; the data
// label says when ball-and-beam's closed loop ignores a loaded file.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QComboBox>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSettings>
#include <QTableWidget>
#include <QTemporaryDir>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "common/import_files.h"
#include "core/dataset.h"
#include "data/csv.h"
#include "gui/import_window.h"
#include "import_dialog.h"
#include "main_window.h"

namespace kfw {
namespace {

class ImportGui : public testing::ImportWindow {
 protected:
  ImportGui() : ImportWindow(4000) {}
};

TEST_F(ImportGui, FourLayoutsMatchTheKfwFile) {
  const Metrics want = open(files.reference, [](ImportDialog&) {});
  // Names that state their units: the guess is complete, nothing to set.
  QString guess_shown;
  const Metrics units = open(files.units, [&](ImportDialog& d) {
    guess_shown = d.findChild<QLabel*>("guess.gyro")->text();
    EXPECT_EQ(d.mapping().at("gyro"), (RoleMapping{"omega_rads", "rad/s"}));
    EXPECT_EQ(d.mapping().at("t"), (RoleMapping{"time_ms", "ms"}));
  });
  EXPECT_EQ(guess_shown, "omega_rads [rad/s]");
  expect_same(units, want, "units");
  // No units in the names: the user sets the roles and the gyro's unit.
  const Metrics german = open(files.german, [](ImportDialog& d) {
    EXPECT_TRUE(d.preview()->item(1, 0)->text().startsWith("0,0035"));  // Zeit, as written
    d.setColumn("t", "Zeit");
    d.setColumn("gyro", "Drehrate");
    d.setUnit("gyro", "rad/s");
    d.setColumn("angle", "Winkel");
    d.setColumn("truth", "Referenz");
  });
  expect_same(german, want, "german");
  expect_same(open(files.tabs, [](ImportDialog&) {}), want, "tabs");
  const Metrics iso =
      open(files.iso, [](ImportDialog& d) { EXPECT_EQ(d.mapping().at("t").unit, "iso"); });
  expect_same(iso, want, "iso");
  EXPECT_EQ(w.dataset()->time_origin, "2024-05-01T10:00:00.000000000Z");
  EXPECT_NE(w.findChild<QLabel*>("dataLabel")->text().indexOf("2024-05-01T10:00:00"), -1);
}

TEST_F(ImportGui, OkIsRefusedWhileARoleIsMissingOrTaken) {
  w.setImportHook([](ImportDialog& d) {
    d.setColumn("gyro", "");
    EXPECT_NE(d.problem().indexOf("'gyro' (required)"), -1) << d.problem().toStdString();
    EXPECT_FALSE(d.okButton()->isEnabled());
    d.setColumn("gyro", "acc_roll_deg");
    EXPECT_NE(d.problem().indexOf("'acc_roll_deg' is assigned to both"), -1);
    return true;  // refused: the dialog still has a problem
  });
  const auto before = w.dataset();
  EXPECT_TRUE(w.openDataset(QString::fromStdString(files.units)).ok());  // nothing changed
  EXPECT_EQ(w.dataset(), before);
}

// The dialog runs the import itself: its error refuses OK before the load is tried; the plot is
// over time; an ISO column of local times is read in the zone typed beside its unit.
TEST_F(ImportGui, TheDialogShowsTheImportsOwnErrorAndReadsLocalTimes) {
  const QString back = dir.filePath("back.csv");
  std::ofstream(back.toStdString()) << "t,gyro,angle\n0,1,2\n0.02,1,2\n0.01,1,2\n";
  w.setImportHook([](ImportDialog& d) {
    EXPECT_NE(d.problem().indexOf("time is not increasing"), -1) << d.problem().toStdString();
    EXPECT_FALSE(d.okButton()->isEnabled());
    return true;  // refused
  });
  const auto before = w.dataset();
  EXPECT_TRUE(w.openDataset(back).ok());
  EXPECT_EQ(w.dataset(), before);

  const QString local = dir.filePath("local.csv");
  std::ofstream(local.toStdString()) << "when,gyro,angle\n2024-03-31T01:59:58,1,2\n"
                                        "2024-03-31T01:59:59,1,2\n2024-03-31T03:00:00,1,2\n";
  w.setImportHook([](ImportDialog& d) {
    EXPECT_EQ(d.mapping().at("t").unit, "iso");
    auto* zone = d.findChild<QLineEdit*>("zone.t");
    EXPECT_NE(zone, nullptr);
    if (!zone) return false;
    zone->setText("Europe/Berlln");
    EXPECT_NE(d.problem().indexOf("unknown time zone 'Europe/Berlln'"), -1)
        << d.problem().toStdString();
    zone->setText("Europe/Berlin");
    EXPECT_EQ(d.problem(), QString());
    EXPECT_EQ(d.mapping().at("t").unit, "iso@Europe/Berlin");
    EXPECT_EQ(d.plot()->xAxis->label(), "t (s)");
    EXPECT_EQ(d.plot()->graph(0)->data()->size(), 3);
    EXPECT_DOUBLE_EQ((d.plot()->graph(0)->data()->constEnd() - 1)->key, 2.0);  // 1 s each
    // KFW_TEST_SHOT_DIR=DIR keeps a picture of the dialog for a human to look at.
    if (const char* shots = std::getenv("KFW_TEST_SHOT_DIR")) {
      d.resize(900, 620);
      d.grab().save(QString(shots) + "/import_dialog.png");
    }
    return true;
  });
  ASSERT_TRUE(w.openDataset(local).ok()) << w.lastError().toStdString();
  w.waitForRun();
  EXPECT_EQ(w.dataset()->source, local.toStdString());
  EXPECT_EQ(w.dataset()->time_origin, "2024-03-31T00:59:58.000000000Z");
  EXPECT_EQ(w.document()->data()->mapping.at("t").unit, "iso@Europe/Berlin");
}

// The preview shows the whole of a long log and says so; the truth is drawn last, dashed, over the
// measurement it follows; the legend has a row of its own (issue 32, item 13).
TEST_F(ImportGui, ThePreviewShowsTheWholeLogAndTheTruthOnTop) {
  QTemporaryDir tmp;
  const QString path = tmp.filePath("long.csv");
  {
    std::ofstream f(path.toStdString());
    f << "zeit_ms;winkel;drehrate;referenz_truth\n";
    for (int k = 0; k < 9715; ++k) {  // 194.3 s at 50 Hz
      const double t = 0.02 * k, a = 5.0 * std::sin(0.1 * t);
      f << 1000.0 * t << ';' << a + 0.3 * std::sin(37.0 * t) << ';' << 0.5 * std::cos(0.1 * t)
        << ';' << a << '\n';
    }
  }
  w.setImportHook([](ImportDialog& d) {
    d.findChild<QComboBox*>("column.t")->setCurrentText("zeit_ms");
    auto* unit = d.findChild<QComboBox*>("unit.t");
    unit->setCurrentIndex(unit->findData("ms"));
    d.findChild<QComboBox*>("column.angle")->setCurrentText("winkel");
    d.findChild<QComboBox*>("column.gyro")->setCurrentText("drehrate");
    d.findChild<QComboBox*>("column.truth")->setCurrentText("referenz_truth");
    EXPECT_EQ(d.problem(), QString()) << d.problem().toStdString();
    QCustomPlot* p = d.plot();
    EXPECT_GE(p->graphCount(), 3);
    double last = 0;
    for (int i = 0; i < p->graphCount(); ++i)
      last = std::max(last, (p->graph(i)->data()->constEnd() - 1)->key);
    EXPECT_NEAR(last, 194.28, 1e-6) << "the preview stops before the log's end";
    const auto* title = p->findChild<QCPTextElement*>("title");
    EXPECT_TRUE(title && title->text().contains("whole file")) << title->text().toStdString();
    QCPGraph* top = p->graph(p->graphCount() - 1);
    EXPECT_TRUE(top->name().startsWith("truth")) << top->name().toStdString();
    EXPECT_EQ(top->pen().style(), Qt::DashLine);
    EXPECT_NE(p->legend->layout(), p->axisRect()->insetLayout()) << "the legend covers the data";
    if (const char* shots = std::getenv("KFW_TEST_SHOT_DIR")) {
      d.resize(900, 720);
      d.grab().save(QString(shots) + "/import_dialog_long.png");
    }
    return true;
  });
  ASSERT_TRUE(w.openDataset(path).ok()) << w.lastError().toStdString();
}

TEST_F(ImportGui, BadFilesKeepThePreviousDataset) {
  const std::string before = w.dataset()->source;
  QString shown;  // what the dialog says
  w.setImportHook([&](ImportDialog& d) {
    shown = d.problem();
    EXPECT_EQ(d.okButton()->isEnabled(), shown.isEmpty());
    return true;
  });
  // A file that reads but does not import: the dialog names the problem and refuses OK.
  std::ofstream(dir.filePath("novalue.csv").toStdString()) << "t,gyro,angle\n0,1,\n1,2,\n";
  EXPECT_TRUE(w.openDataset(dir.filePath("novalue.csv")).ok());  // refused: nothing changes
  EXPECT_NE(shown.indexOf("novalue.csv: column 'angle' has no value"), -1) << shown.toStdString();
  EXPECT_EQ(w.dataset()->source, before);
  // Files that do not read: an error before any dialog.
  const std::pair<std::string, std::string> cases[] = {
      {"empty.csv", ": empty file"},
      {"header.csv", ": no data rows after the header"},
      {"binary.csv", "binary.csv:2: not a text file"},
  };
  std::ofstream(dir.filePath("empty.csv").toStdString());
  std::ofstream(dir.filePath("header.csv").toStdString()) << "t,gyro,angle\n";
  std::ofstream(dir.filePath("binary.csv").toStdString(), std::ios::binary)
      << std::string("t,gyro\n\x00\x01\x02", 10);
  for (const auto& [name, fragment] : cases) {
    const auto st = w.openDataset(dir.filePath(QString::fromStdString(name)));
    ASSERT_FALSE(st.ok()) << name;
    EXPECT_NE(st.error().find(name), std::string::npos) << st.error();
    EXPECT_NE(st.error().find(fragment), std::string::npos) << st.error();
    EXPECT_EQ(w.dataset()->source, before) << name;
    EXPECT_NE(w.lastError().indexOf(QString::fromStdString(name)), -1);
  }
}

TEST_F(ImportGui, MappingEditsAreUndoableAndDataCanBeSavedConverted) {
  w.setImportHook([](ImportDialog&) { return true; });
  ASSERT_TRUE(w.openDataset(QString::fromStdString(files.units)).ok());
  ASSERT_TRUE(w.waitForRun());
  const double rmse = w.result()->metrics.at("rmse");
  // Data ▸ Mapping…: flip the gyro (a different run), then undo restores the mapping and RMSE.
  w.setImportHook([](ImportDialog& d) {
    d.setFlip("gyro", true);
    return true;
  });
  ASSERT_TRUE(w.editMapping().ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(w.document()->data()->mapping.at("gyro").flip);
  EXPECT_NE(w.result()->metrics.at("rmse"), rmse);
  ASSERT_TRUE(w.undo());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_FALSE(w.document()->data()->mapping.at("gyro").flip);
  EXPECT_EQ(w.result()->metrics.at("rmse"), rmse);
  // Save as kfw CSV: the converted data, readable without any mapping.
  const QString out = dir.filePath("converted.csv");
  ASSERT_TRUE(w.saveConvertedCsv(out).ok());
  EXPECT_FALSE(w.saveConvertedCsv(QString::fromStdString(files.units)).ok());  // the input
  auto back = read_csv(out.toStdString());
  ASSERT_TRUE(back.ok()) << back.error();
  auto ref = read_csv(files.reference);
  ASSERT_TRUE(ref.ok());
  for (const char* c : {"t", "gyro", "angle", "truth"}) {
    for (std::size_t i = 0; i < ref->rows(); i += 97)
      EXPECT_TRUE(testing::close12(back->col(c)[i], ref->col(c)[i])) << c << " row " << i;
  }
  // The Data tab plots any column over time.
  auto* combo = w.dataColumnCombo();
  const int i = combo->findText("gyro");
  ASSERT_GE(i, 0);
  combo->setCurrentIndex(i);
  ASSERT_EQ(w.dataPlot()->graphCount(), 1);
  EXPECT_EQ(w.dataPlot()->graph(0)->data()->size(), static_cast<int>(files.rows));
  // Forget: the next open starts from the guess again (the remembered flip is gone).
  ASSERT_TRUE(w.forgetMapping().ok());
}

TEST(ImportGuiState, ClosedLoopSaysTheFileIsNotUsed) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("ballbeam", {}, {"sim.duration=5"}).ok());
  ASSERT_TRUE(w.waitForRun());
  QTemporaryDir dir;
  const QString csv = dir.filePath("bb.csv");
  auto d = w.scenario()->simulate(w.values());
  ASSERT_TRUE(d.ok());
  ASSERT_TRUE(write_csv_file(csv.toStdString(), *d).ok());
  ASSERT_TRUE(w.openDataset(csv).ok());
  ASSERT_TRUE(w.waitForRun());
  auto* label = w.findChild<QLabel*>("dataLabel");
  auto* fix = w.findChild<QPushButton*>("useDataMode");
  ASSERT_NE(fix, nullptr);
  if (w.values().at("mode") == 0.0) {  // closed
    EXPECT_NE(label->text().indexOf("not used"), -1) << label->text().toStdString();
    EXPECT_TRUE(fix->isVisibleTo(&w));
    fix->click();
    ASSERT_TRUE(w.waitForRun());
  }
  EXPECT_EQ(w.values().at("mode"), 1.0);
  EXPECT_EQ(label->text().indexOf("not used"), -1) << label->text().toStdString();
  EXPECT_FALSE(fix->isVisibleTo(&w));
}

}  // namespace
}  // namespace kfw
