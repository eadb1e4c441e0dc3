// File → Export plots… offers what kfw --export takes (issue 32, item 11): the plots, the formats
// and a paper size; the files written are those chosen, at the size chosen.
#include <gtest/gtest.h>

#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <cstdlib>

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

// A column-wide figure (issue 32, item 12): the predicted line shows over the sensor's dots
// (line 7 743 px against 56 346 px of dots before; 30 740 against 30 689 now).
TEST(ExportDialog, AColumnFigureShowsTheLineOverTheDots) {
  QTemporaryDir dir;
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter").ok());
  ASSERT_TRUE(w.waitForRun());
  ExportSpec spec;
  ASSERT_TRUE(parseSize("column", 300, spec).ok());
  spec.dpi = 300;
  auto files = w.exportController()->exportAll(dir.path(), {"png"}, spec, {"measured.angle.angle"});
  ASSERT_TRUE(files.ok()) << files.error();
  const QImage png(dir.filePath("helicopter_measured.angle.angle.png"));
  ASSERT_FALSE(png.isNull());
  long line = 0, dots = 0;
  for (int y = 0; y < png.height(); ++y) {
    for (int x = 0; x < png.width(); ++x) {
      const QColor c = png.pixelColor(x, y);
      if (std::abs(c.red() - 31) < 40 && std::abs(c.green() - 119) < 40 && c.blue() > 140) ++line;
      if (std::abs(c.red() - c.green()) < 12 && c.red() > 110 && c.red() < 190) ++dots;
    }
  }
  EXPECT_GT(line, dots / 3) << "the dots hide the line";
}

}  // namespace
}  // namespace kfw
