// Fails when the glyphs our labels use would render as boxes (no font with them installed).
#include <gtest/gtest.h>

#include <QApplication>
#include <QFontDatabase>
#include <QFontMetrics>
#include <QImage>
#include <QPainter>
#include <QRawFont>

namespace {

TEST(Fonts, DejaVuSansIsInstalled) {
  EXPECT_TRUE(QFontDatabase::families().contains("DejaVu Sans"))
      << "install fonts-dejavu-core; families: "
      << QFontDatabase::families().join(", ").toStdString();
}

TEST(Fonts, LabelGlyphsExistInTheApplicationFont) {
  const QString glyphs = QString::fromUtf8("θβγσλαψμχΔ±²⁻√°ω̂·–×≈");
  const QRawFont raw = QRawFont::fromFont(QApplication::font());
  ASSERT_TRUE(raw.isValid());
  for (const QChar c : glyphs) {
    if (c.category() == QChar::Mark_NonSpacing) continue;  // combining hat
    EXPECT_TRUE(raw.supportsCharacter(c))
        << "missing glyph U+" << std::hex << static_cast<int>(c.unicode()) << " in "
        << raw.familyName().toStdString();
  }
}

TEST(Fonts, TextRendersInk) {
  QImage img(200, 40, QImage::Format_RGB32);
  img.fill(Qt::white);
  {
    QPainter p(&img);
    p.setFont(QApplication::font());
    p.drawText(5, 25, QString::fromUtf8("θ̂ ± 2σ (deg²)"));
  }
  int dark = 0;
  for (int y = 0; y < img.height(); ++y) {
    for (int x = 0; x < img.width(); ++x)
      dark += qGray(img.pixel(x, y)) < 128;
  }
  EXPECT_GT(dark, 50);
}

}  // namespace
