// kfw --screenshot honours --size WxH (pixels): the PNG has that size; a physical or named size,
// or one no screen has, is an argument error (exit 2, no file). And the issue's export command
// itself, through the command line: --export --size 3.5inx2.5in --dpi 300 writes 1050×750 px
// PNGs and 252×180 pt PDFs (the text size in those PDFs: PaperExport in export_paper_test.cpp).
#include <gtest/gtest.h>

#include <QFileInfo>
#include <QImage>
#include <QTemporaryDir>
#include <string>

#include "app_options.h"
#include "common/cli_runner.h"

namespace kfw {
namespace {

QSize sizeOf(const QStringList& args) {
  auto o = parseAppOptions(args);
  EXPECT_TRUE(o.ok()) << o.error();
  if (!o) return {};
  auto s = screenshotSize(*o);
  return s ? *s : QSize();
}

TEST(ScreenshotSize, PixelsOrTheDefaults) {
  EXPECT_EQ(sizeOf({"--screenshot", "a.png"}), QSize(1600, 1000));
  EXPECT_EQ(sizeOf({"--screenshot", "a.png", "--present"}), QSize(1366, 768));
  EXPECT_EQ(sizeOf({"--screenshot", "a.png", "--size", "1280x720"}), QSize(1280, 720));
  EXPECT_EQ(sizeOf({"--screenshot", "a.png", "--size", "1366pxx768px"}), QSize(1366, 768));
  EXPECT_EQ(sizeOf({"--screenshot", "a.png", "--size", "1024x600", "--present"}), QSize(1024, 600));
  for (const char* bad : {"3.5inx2.5in", "column", "100x100", "9000x600", "12.5x600", "1366"}) {
    auto o = parseAppOptions({"--screenshot", "a.png", "--size", bad});
    ASSERT_TRUE(o.ok()) << o.error();
    auto s = screenshotSize(*o);
    EXPECT_FALSE(s.ok()) << bad;
    if (!s) {
      EXPECT_NE(s.error().find("--size"), std::string::npos) << s.error();
    }
  }
}

TEST(ScreenshotSize, TheWindowIsShotAtTheGivenSize) {
  QTemporaryDir dir;
  const QString a = dir.filePath("a.png");
  auto r = testing::run_command(std::string(KFW_GUI) + " --screenshot " + a.toStdString() +
                                " --size 1366x768 helicopter 2>&1 >/dev/null");
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(r.text, "");
  const QImage img(a);
  ASSERT_FALSE(img.isNull());
  EXPECT_EQ(img.size(), QSize(1366, 768));

  const QString b = dir.filePath("b.png");
  auto bad = testing::run_command(std::string(KFW_GUI) + " --screenshot " + b.toStdString() +
                                  " --size column helicopter 2>&1");
  EXPECT_EQ(bad.code, 2) << bad.text;
  EXPECT_NE(bad.text.find("pixels"), std::string::npos) << bad.text;
  EXPECT_FALSE(QFileInfo::exists(b));
}

TEST(ScreenshotSize, ExportCommandOfTheIssueWritesColumnSizedFiles) {
  if (testing::run_command("command -v pdfinfo").code != 0) {
    GTEST_SKIP() << "pdfinfo (poppler-utils, scripts/setup.sh) is not installed";
  }
  QTemporaryDir dir;
  const std::string out = dir.path().toStdString();
  auto r =
      testing::run_command(std::string(KFW_GUI) + " --export " + out +
                           " helicopter --set sim.duration=10 --plot state.theta --plot nis.angle"
                           " --format png,pdf --size 3.5inx2.5in --dpi 300 2>&1 >/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(r.text, "");
  for (const char* plot : {"state.theta", "nis.angle"}) {
    const QImage img(dir.filePath(QString("helicopter_%1.png").arg(plot)));
    ASSERT_FALSE(img.isNull()) << plot;
    EXPECT_EQ(img.size(), QSize(1050, 750)) << plot;
    auto info = testing::run_command(
        "pdfinfo " + dir.filePath(QString("helicopter_%1.pdf").arg(plot)).toStdString() + " 2>&1");
    ASSERT_EQ(info.code, 0) << info.text;
    EXPECT_NE(info.text.find("252 x 180 pts"), std::string::npos) << info.text;
  }
}

}  // namespace
}  // namespace kfw
