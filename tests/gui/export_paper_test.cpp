// Exports fit for papers: --size / --dpi / --font-scale give a PNG of W×H×dpi pixels and a PDF page
// of the physical size whose smallest text (measured by pdftotext -bbox) is ≥ 7 pt; SVG titles in
// one text run; every consistency channel exported; --plot picks plots; all or nothing.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QDir>
#include <QFile>
#include <QImage>
#include <QRegularExpression>
#include <QTemporaryDir>
#include <string>

#include "common/cli_runner.h"
#include "common/gui_util.h"
#include "consistency_panel.h"
#include "main_window.h"
#include "plot_export.h"

namespace kfw {
namespace {

using testing::readAll;

// The text size (pt) of every word pdftotext finds on the page, and the page size. A word's box
// is as tall as its font's line (≈ 1.16 × its size for DejaVu Sans); a y-axis label is rotated,
// its box tall and narrow, so its width is that height. A single character: the larger side.
struct PdfText {
  double page_w = 0, page_h = 0;
  std::vector<double> heights;
  QStringList words;
};

PdfText measurePdf(const QString& pdf) {
  PdfText out;
  const auto r = testing::run_command("pdftotext -bbox '" + pdf.toStdString() + "' - 2>&1");
  const QString html = QString::fromStdString(r.text);
  static const QRegularExpression page(R"re(<page width="([0-9.]+)" height="([0-9.]+)")re");
  const auto pm = page.match(html);
  if (pm.hasMatch()) {
    out.page_w = pm.captured(1).toDouble();
    out.page_h = pm.captured(2).toDouble();
  }
  static const QRegularExpression word(
      R"re(<word xMin="([0-9.]+)" yMin="([0-9.]+)" xMax="([0-9.]+)" yMax="([0-9.]+)">([^<]*)</word>)re");
  auto it = word.globalMatch(html);
  while (it.hasNext()) {
    const auto m = it.next();
    const double w = m.captured(3).toDouble() - m.captured(1).toDouble();
    const double h = m.captured(4).toDouble() - m.captured(2).toDouble();
    const QString text = m.captured(5);
    out.heights.push_back(text.size() <= 1 ? std::max(w, h) : (h > 1.5 * w ? w : h));
    out.words << text;
  }
  return out;
}

class PaperExport : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w_.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
    ASSERT_TRUE(w_.waitForRun());
  }
  MainWindow w_;
};

TEST_F(PaperExport, ColumnSizeAt300DpiIsExactInPixelsAndPointsWithTextOf7PtOrMore) {
  if (testing::run_command("command -v pdftotext").code != 0) {
    GTEST_SKIP() << "pdftotext (poppler-utils, scripts/setup.sh) is not installed";
  }
  ExportSpec spec;
  ASSERT_TRUE(parseSize("3.5inx2.5in", 300, spec).ok());
  spec.dpi = 300;
  QTemporaryDir dir;
  auto files = w_.exportAll(dir.path(), {"png", "pdf"}, spec);
  ASSERT_TRUE(files.ok()) << files.error();
  ASSERT_EQ(files->size(), 2 * w_.exportedPlots().size());
  double smallest = 1e9;
  QString smallest_word;
  for (const QString& f : *files) {
    if (f.endsWith(".png")) {
      const QImage img(f);
      EXPECT_EQ(img.width(), 1050) << f.toStdString();
      EXPECT_EQ(img.height(), 750) << f.toStdString();
      EXPECT_NEAR(img.dotsPerMeterX() * 0.0254, 300.0, 0.5);
      continue;
    }
    const PdfText t = measurePdf(f);
    EXPECT_NEAR(t.page_w, 252.0, 0.01) << f.toStdString();
    EXPECT_NEAR(t.page_h, 180.0, 0.01) << f.toStdString();
    ASSERT_FALSE(t.heights.empty()) << "no text in " << f.toStdString();
    for (std::size_t i = 0; i < t.heights.size(); ++i) {
      if (t.heights[i] < smallest) {
        smallest = t.heights[i];
        smallest_word = t.words[static_cast<int>(i)] + " in " + f;
      }
    }
  }
  EXPECT_GE(smallest, 7.0) << smallest_word.toStdString();
}

TEST_F(PaperExport, NamedSizesUnitsAndFontScale) {
  ExportSpec s;
  ASSERT_TRUE(parseSize("column", 300, s).ok());
  EXPECT_DOUBLE_EQ(s.width_in, 3.5);
  ASSERT_TRUE(parseSize("page", 300, s).ok());
  EXPECT_DOUBLE_EQ(s.width_in, 7.0);
  ASSERT_TRUE(parseSize("89x60mm", 300, s).ok());
  EXPECT_NEAR(s.width_in, 89 / 25.4, 1e-12);
  EXPECT_NEAR(s.height_in, 60 / 25.4, 1e-12);
  ASSERT_TRUE(parseSize("1200x700", 96, s).ok());
  EXPECT_EQ(s.layoutWidth(), 1200);
  EXPECT_EQ(s.layoutHeight(), 700);
  EXPECT_FALSE(parseSize("3.5x", 300, s).ok());
  EXPECT_FALSE(parseSize("0.1inx2in", 300, s).ok());
  EXPECT_NE(parseSize("big", 300, s).error().find("column"), std::string::npos);

  // --font-scale 2: the title's font is twice as large in the export, and as before afterwards.
  QCustomPlot* p = w_.plots().front().plot;
  auto* title = p->findChild<QCPTextElement*>("title");
  ASSERT_NE(title, nullptr);
  const double before = title->font().pointSizeF();
  ExportSpec big;
  big.font_scale = 2.0;
  QTemporaryDir dir;
  const QList<ExportItem> one{ExportItem{"probe", "", p, {}}};
  // The title row of the PNG: more dark pixels at scale 2.
  auto darkRows = [](const QString& f) {
    const QImage img(f);
    int dark = 0;
    for (int y = 0; y < img.height() / 8; ++y)
      for (int x = 0; x < img.width(); ++x)
        dark += qGray(img.pixel(x, y)) < 100;
    return dark;
  };
  auto a = exportItems(one, dir.path(), {"png"}, "a_", ExportSpec{});
  auto b = exportItems(one, dir.path(), {"png"}, "b_", big);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_GT(darkRows(b->front()), 2 * darkRows(a->front()));
  EXPECT_DOUBLE_EQ(title->font().pointSizeF(), before);
}

TEST_F(PaperExport, SvgTitlesAreOneTextRunEach) {
  QTemporaryDir dir;
  auto files = w_.exportAll(dir.path(), {"svg"});
  ASSERT_TRUE(files.ok()) << files.error();
  int checked = 0;
  for (const ExportItem& item : w_.exportedPlots()) {
    auto* title = item.plot->findChild<QCPTextElement*>("title");
    if (!title) continue;
    const QString svg =
        QString::fromUtf8(readAll(dir.filePath("helicopter_" + item.name + ".svg")));
    ASSERT_FALSE(svg.isEmpty()) << item.name.toStdString();
    // The title's text, whole, inside one <text> element (XML-escaped as the generator writes it).
    // (on screen a title wraps to its plot's width; the export wraps it to the export's)
    const QString text = QString(title->text()).replace('\n', ' ').toHtmlEscaped();
    EXPECT_TRUE(svg.contains(
        QRegularExpression(">\\s*" + QRegularExpression::escape(text) + "\\s*</text>")))
        << item.name.toStdString() << ": " << text.toStdString();
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TEST(ConsistencyExport, EveryChannelIsExported) {
  // Underwater's five channels (radome's four until its preset became a model file, issue 28).
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("underwater").ok());
  ASSERT_TRUE(w.waitForRun(60000));
  const QStringList names = w.plotNames();
  int nis = 0;
  for (const auto& c : w.result()->channels()) {
    EXPECT_TRUE(names.contains("consistency_nis." + QString::fromStdString(c.name)))
        << c.name << " in " << names.join(' ').toStdString();
    ++nis;
  }
  EXPECT_EQ(nis, 5);
  w.consistency()->setChannel(2);
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"}, {}, {"consistency_nis"});
  ASSERT_TRUE(files.ok()) << files.error();
  ASSERT_EQ(files->size(), 5);
  // Five channels, five different pictures; the user's channel is shown again afterwards.
  QSet<QByteArray> distinct;
  for (const QString& f : *files)
    distinct.insert(readAll(f));
  EXPECT_EQ(distinct.size(), 5);
  EXPECT_EQ(w.consistency()->channel(), 2);
}

TEST_F(PaperExport, PlotSelectionAndUnknownNames) {
  QTemporaryDir dir;
  auto files = w_.exportAll(dir.path(), {"png", "svg"}, {}, {"state.theta"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(*files, (QStringList{dir.filePath("helicopter_state.theta.png"),
                                 dir.filePath("helicopter_state.theta.svg")}));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files).size(), 2);
  auto bad = w_.exportAll(dir.path(), {"png"}, {}, {"state.thet"});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.err().exit_code, kExitInvalid);
  EXPECT_NE(bad.error().find("did you mean 'state.theta'"), std::string::npos) << bad.error();
}

TEST_F(PaperExport, AllOrNothing) {
  QTemporaryDir dir;
  // One target is a directory: refused before anything is drawn or written.
  ASSERT_TRUE(QDir(dir.path()).mkpath("helicopter_gain.pdf"));
  auto r = w_.exportAll(dir.path(), {"png", "pdf"});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 0)
      << QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).join(' ').toStdString();
}

TEST_F(PaperExport, DarkThemeExportLeavesTheWindowLight) {
  QTemporaryDir dir;
  ExportSpec dark;
  dark.theme = Theme::kDark;
  auto files = w_.exportAll(dir.path(), {"png"}, dark, {"state.theta"});
  ASSERT_TRUE(files.ok()) << files.error();
  const QImage img(files->front());
  EXPECT_LT(qGray(img.pixel(2, 2)), 80);
  QCustomPlot* p = w_.plots().front().plot;
  EXPECT_EQ(currentTheme(p), Theme::kLight);
  const QImage screen = p->toPixmap(200, 150).toImage();
  EXPECT_GT(qGray(screen.pixel(2, 2)), 200);
}

TEST_F(PaperExport, PdfHasNoCreationDateUnlessSourceDateEpoch) {
  QTemporaryDir dir;
  auto a = w_.exportAll(dir.path(), {"pdf"}, {}, {"state.theta"});
  ASSERT_TRUE(a.ok()) << a.error();
  EXPECT_FALSE(readAll(a->front()).contains("/CreationDate"));
  qputenv("SOURCE_DATE_EPOCH", "1700000000");
  auto b = w_.exportAll(dir.path(), {"pdf"}, {}, {"state.theta"});
  qunsetenv("SOURCE_DATE_EPOCH");
  ASSERT_TRUE(b.ok()) << b.error();
  EXPECT_TRUE(readAll(b->front()).contains("/CreationDate (D:20231114221320Z)"));
  if (testing::run_command("command -v pdfinfo").code == 0) {
    const auto info = testing::run_command("pdfinfo '" + b->front().toStdString() + "' 2>&1");
    EXPECT_EQ(info.code, 0) << info.text;  // the in-place edit keeps the PDF valid
    EXPECT_NE(info.text.find("2023"), std::string::npos) << info.text;
  }
}

}  // namespace
}  // namespace kfw
