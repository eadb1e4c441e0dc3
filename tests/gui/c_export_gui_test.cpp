// File → Export filter as C… (issue 31): the window writes the bytes kfw-cli export-c writes for
// the same preset and values, and a model it cannot export is refused with nothing written.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QDialogButtonBox>
#include <QDir>
#include <QFile>
#include <QLineEdit>
#include <QMenuBar>
#include <QPushButton>
#include <QTemporaryDir>
#include <QTimer>

#include "common/cli_runner.h"
#include "main_window.h"

namespace kfw {
namespace {

QByteArray c_file(const QString& path) {
  QFile f(path);
  return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
}

TEST(CExportGui, TheWindowWritesTheBytesOfTheCommandLine) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/models/range_bearing.json").ok());
  ASSERT_TRUE(w.waitForRun());
  w.setParam("sigma_a", 0.7);
  ASSERT_TRUE(w.waitForRun());
  bool listed = false;
  for (QAction* a : w.menuBar()->actions().front()->menu()->actions())
    listed = listed || a->text().remove('&') == "Export filter as C…";
  EXPECT_TRUE(listed);
  QTemporaryDir gui, cli;
  for (const bool single : {false, true}) {
    ASSERT_TRUE(w.exportFilterAsC(gui.path(), "", single, false).ok());
    const auto out = testing::run_command(
        std::string(KFW_CLI_FOR_GUI_TESTS) + " export-c " + KFW_SOURCE_DIR +
        "/presets/models/range_bearing.json --set sigma_a=0.7" + (single ? " --float" : "") +
        " --out-dir " + cli.path().toStdString() + " 2>&1");
    ASSERT_EQ(out.code, 0) << out.text;
    for (const char* f : {"/range_bearing.h", "/range_bearing.c", "/range_bearing_example.c"}) {
      const QByteArray a = c_file(gui.path() + f);
      EXPECT_FALSE(a.isEmpty()) << f;
      EXPECT_EQ(a, c_file(cli.path() + f)) << f;
    }
  }
}

// The dialog asks for the folder, the prefix (the preset's name), the precision and the steady
// gain, fits a 1280 × 720 screen, and its OK writes the files. KFW_SHOT=DIR saves a picture.
TEST(CExportGui, TheDialogAsksWhereAndHowAndWrites) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/models/cv1d.json").ok());
  ASSERT_TRUE(w.waitForRun());
  QTemporaryDir dir;
  bool seen = false;
  QTimer::singleShot(0, [&] {
    QWidget* d = QApplication::activeModalWidget();
    if (!d) return;
    seen = true;
    const auto edits = d->findChildren<QLineEdit*>();
    const auto boxes = d->findChildren<QCheckBox*>();
    EXPECT_EQ(edits.size(), 2);
    EXPECT_EQ(boxes.size(), 2);
    EXPECT_LE(d->sizeHint().width(), 1280);
    EXPECT_LE(d->sizeHint().height(), 720);
    if (const char* shot = std::getenv("KFW_SHOT")) d->grab().save(QString(shot) + "/c_export.png");
    if (edits.size() == 2) {
      EXPECT_EQ(edits[1]->text(), "cv1d");
      edits[0]->setText(dir.path());
    }
    auto* box = d->findChild<QDialogButtonBox*>();
    if (box) box->button(QDialogButtonBox::Ok)->click();
  });
  w.exportFilterAsCWithDialog();
  EXPECT_TRUE(seen);
  for (const char* f : {"/cv1d.h", "/cv1d.c", "/cv1d_example.c"})
    EXPECT_TRUE(QFile::exists(dir.path() + f)) << f;
}

TEST(CExportGui, AModelItCannotExportIsRefusedWithNothingWritten) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/radome.json").ok());
  ASSERT_TRUE(w.waitForRun());
  w.setParam("Kp", 0.1);  // the grid renewed at run time: not exported yet
  ASSERT_TRUE(w.waitForRun());
  QTemporaryDir dir;
  const Status st = w.exportFilterAsC(dir.path(), "", false, false);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("model.modes.renewal"), std::string::npos) << st.error();
  EXPECT_TRUE(QDir(dir.path()).entryList(QDir::NoDotAndDotDot | QDir::AllEntries).isEmpty());
}

}  // namespace
}  // namespace kfw
