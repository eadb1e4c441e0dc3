// Writes plots to PNG / PDF / SVG at a requested physical size, with or without a display.
//
// A figure is laid out at 96 layout pixels per inch (the screen's scale, at which a 9-pt label
// is 9 pt on paper): a PNG of W × H inches at D dpi is W·D × H·D pixels, a PDF page is
// W·72 × H·72 pt and an SVG is W × H inches. Outputs carry no time stamp (PDF: no creation date
// unless SOURCE_DATE_EPOCH gives one), so two exports of the same plot are byte-identical.
#pragma once

#include <QByteArray>
#include <QImage>
#include <QList>
#include <QString>
#include <QStringList>
#include <functional>

#include "core/expected.h"
#include "plot_look.h"
#include "scenario_view.h"

namespace kfw {

// Layout pixels per inch of an exported figure.
inline constexpr double kLayoutDpi = 96.0;
inline constexpr int kExportWidth = 1200;  // px at 96 dpi, when no --size is given
inline constexpr int kExportHeight = 700;

struct ExportSpec {
  double width_in = kExportWidth / kLayoutDpi;
  double height_in = kExportHeight / kLayoutDpi;
  double dpi = kLayoutDpi;  // PNG pixels per inch
  double font_scale = 1.0;  // every text of the plot × this
  Theme theme = Theme::kLight;
  // Layout size (px at kLayoutDpi).
  int layoutWidth() const;
  int layoutHeight() const;
};

// Parses --size: "WxH" with a unit on each or both (px, in, mm; "3.5inx2.5in", "90x60mm",
// "1200x700", "1200x700px") or a named size: "column" (3.5 × 2.5 in, one column of a two-column
// paper) or "page" (7 × 4 in, the text width of a page). Pixel sizes are at `dpi`.
Status parseSize(const QString& text, double dpi, ExportSpec& spec);
Expected<Theme> parseTheme(const QString& text);

// One exported plot: the file stem, the plot, and what to do before drawing it (the consistency
// panel draws one channel at a time into the same plots).
struct ExportItem {
  QString name;
  QString title;
  QCustomPlot* plot = nullptr;
  std::function<void()> prepare;
};

// One plot in one format ("png", "pdf", "svg"), as the bytes of the file.
Expected<QByteArray> renderPlot(QCustomPlot* plot, const QString& format, const ExportSpec& spec);
// One plot to one file; the format comes from the extension (.png, .pdf, .svg).
Status exportPlot(QCustomPlot* plot, const QString& path, const ExportSpec& spec = {});
// Every item in every format into dir (created if needed), all or nothing: every file is drawn
// first, then all are written through temporaries and renamed. Returns the files written.
Expected<QStringList> exportItems(const QList<ExportItem>& items, const QString& dir,
                                  const QStringList& formats, const QString& prefix = {},
                                  const ExportSpec& spec = {});
// Parses "png,pdf,svg"; the message names an unknown format.
Expected<QStringList> parseFormats(const QString& list);

// kfw --screenshot: the path checked before the run as every output is (data/output.h: not a
// directory, device or input; its folder writable) and its suffix a format Qt writes (png, jpg,
// bmp, …), exit 2; then the image written through the one atomic writer (old or new file).
Status checkScreenshotPath(const QString& path);
Status saveScreenshot(const QImage& image, const QString& path);
// The items whose name is one of `wanted` (or "wanted.<anything>": consistency_nis selects every
// channel's). An unknown name is an Error (exit 2) with the nearest known name.
Expected<QList<ExportItem>> selectItems(const QList<ExportItem>& items, const QStringList& wanted);

}  // namespace kfw
