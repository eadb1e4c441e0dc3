// File → Export plots… offers what kfw --export takes (issue 32, item 11): the plots, the formats
// and a paper size; the files written are those chosen, at the size chosen.
#include <gtest/gtest.h>

#include <QDir>
#include <QImage>
#include <QTemporaryDir>

#include "export_controller.h"
#include "export_dialog.h"
#include "main_window.h"

namespace kfw {
namespace {

TEST(ExportDialog, WritesTheChosenPlotsFormatsAndSize) {
  QTemporaryDir dir;
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/cv1d").ok());
  ASSERT_TRUE(w.waitForRun());
  ExportController* e = w.exportController();
  e->setDialogHook([&](ExportDialog& d) {
    d.setFolder(dir.path());
    d.setChosenPlots({"state.x", "gain"});
    d.setFormats({"png"});
    d.setSize("column");
    d.setDpi(300);
    return true;
  });
  e->exportWithDialog();
  const QStringList files = QDir(dir.path()).entryList({"*.*"}, QDir::Files, QDir::Name);
  EXPECT_EQ(files, (QStringList{"cv1d_gain.png", "cv1d_state.x.png"}));
  const QImage png(dir.filePath("cv1d_state.x.png"));
  EXPECT_EQ(png.size(), QSize(1050, 750));  // 3.5 × 2.5 in at 300 dpi
  // A size it cannot read is refused, naming it; nothing is written.
  QTemporaryDir other;
  ExportDialog d(e->plotNames());
  d.setFolder(other.path());
  d.setSize("12 by 7");
  const Status st = e->exportFromDialog(d);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("12 by 7"), std::string::npos) << st.error();
  EXPECT_TRUE(QDir(other.path()).isEmpty());
}

}  // namespace
}  // namespace kfw
