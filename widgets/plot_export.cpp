#include "plot_export.h"

#include <qcustomplot.h>

#include <QBuffer>
#include <QDateTime>
#include <QDir>
#include <QFileInfo>
#include <QFontMetricsF>
#include <QImage>
#include <QImageWriter>
#include <QPageSize>
#include <QPdfWriter>
#include <QRegularExpression>
#include <QSvgGenerator>
#include <cmath>
#include <vector>

#include "core/limits.h"
#include "core/suggest.h"
#include "data/output.h"
#include "plot_kit.h"
#include "plot_look.h"

namespace kfw {

namespace {

// Everything an export changes on a live plot (theme, font scale, antialiasing), undone when it
// goes out of scope so the window looks as before. Titles wider than the figure are wrapped.
class ExportLook {
 public:
  ExportLook(QCustomPlot* p, const ExportSpec& spec) : p_(p), before_(plotLook(p)) {
    plot::setExportLook(p_, true);
    p_->setProperty(kExportingProperty, true);  // titles keep the export's wrap (plot_look.h)
    setPlotLook(p_, {spec.theme, spec.font_scale, false});
    // QCustomPlot draws a log axis' exponents at int(0.75 × the tick font's whole points): 6 pt
    // under 9-pt ticks. At least 7 pt on paper: such ticks get 10 pt (× the font scale).
    for (QCPAxisRect* r : p_->axisRects()) {
      for (QCPAxis* a : r->axes()) {
        const QFont f = a->tickLabelFont();
        const double floor_pt = 10.0 * std::min(1.0, spec.font_scale);
        if (a->scaleType() != QCPAxis::stLogarithmic || f.pointSizeF() >= floor_pt) continue;
        QFont g = f;
        g.setPointSizeF(floor_pt);
        a->setTickLabelFont(g);
        ticks_.push_back({a, f});
      }
    }
    // A column-wide figure has room for fewer tick labels along x than the screen's (labels
    // ran into each other): about one per inch.
    const int room = std::max(3, static_cast<int>(spec.width_in / std::max(1.0, spec.font_scale)));
    for (QCPAxisRect* r : p_->axisRects()) {
      for (QCPAxis* a : r->axes(QCPAxis::atBottom | QCPAxis::atTop)) {
        QSharedPointer<QCPAxisTicker> t = a->ticker();
        if (!t || t->tickCount() <= room) continue;
        tick_counts_.push_back({t, t->tickCount()});
        t->setTickCount(room);
      }
    }
    for (QCPLayoutElement* e : p_->plotLayout()->elements(true)) {
      auto* t = qobject_cast<QCPTextElement*>(e);
      if (!t) continue;
      titles_.push_back({t, t->text()});
      QString text = t->text();  // unwrapped (presentation mode wraps titles to the screen)
      text.replace('\n', ' ');
      t->setText(wrapText(text, t->font(), spec.layoutWidth() - 12));
    }
    if (spec.layoutWidth() < kNarrowLayout) narrow();
    // The legend's columns for the figure's width.
    legend_wrap_ = p_->legend ? p_->legend->wrap() : 0;
    plot::fitLegend(p_, spec.layoutWidth());
  }
  // A column-wide figure (issue 32, item 12): the sensor's dots smaller and, in a plot with dots,
  // the lines over them stronger (the dots hid the estimate and truth); the legend's icons
  // shorter and its rows tighter (it took a fifth of the height).
  void narrow() {
    bool dots = false;
    for (int i = 0; i < p_->graphCount(); ++i) {
      const QCPGraph* g = p_->graph(i);
      dots = dots || (g->lineStyle() == QCPGraph::lsNone &&
                      g->scatterStyle().shape() == QCPScatterStyle::ssSquare);
    }
    for (int i = 0; i < p_->graphCount(); ++i) {
      QCPGraph* g = p_->graph(i);
      styles_.push_back({g, g->scatterStyle(), g->pen()});
      if (g->lineStyle() == QCPGraph::lsNone &&
          g->scatterStyle().shape() == QCPScatterStyle::ssSquare) {
        QCPScatterStyle s = g->scatterStyle();
        s.setSize(kNarrowDot);
        g->setScatterStyle(s);
      } else if (dots && g->lineStyle() != QCPGraph::lsNone && g->pen().widthF() < kNarrowLine) {
        QPen pen = g->pen();
        pen.setWidthF(kNarrowLine);
        g->setPen(pen);
      }
    }
    if (QCPLegend* l = p_->legend) {
      legend_icon_ = l->iconSize();
      legend_spacing_ = l->rowSpacing();
      l->setIconSize(QSize(16, 8));
      l->setRowSpacing(-3);
    }
  }
  ~ExportLook() {
    p_->setProperty(kExportingProperty, QVariant());
    for (const auto& [t, count] : tick_counts_)
      t->setTickCount(count);
    for (const auto& [t, text] : titles_)
      t->setText(text);
    for (const auto& [a, f] : ticks_)
      a->setTickLabelFont(f);
    for (const auto& s : styles_) {
      s.graph->setScatterStyle(s.scatter);
      s.graph->setPen(s.pen);
    }
    if (p_->legend && legend_icon_.isValid()) {
      p_->legend->setIconSize(legend_icon_);
      p_->legend->setRowSpacing(legend_spacing_);
    }
    setPlotLook(p_, before_);
    if (p_->legend && p_->legend->wrap() != legend_wrap_) {
      p_->legend->setWrap(legend_wrap_);
      p_->legend->setFillOrder(p_->legend->fillOrder(), true);
    }
    plot::setExportLook(p_, false);
    p_->replot(QCustomPlot::rpQueuedReplot);
  }
  ExportLook(const ExportLook&) = delete;
  ExportLook& operator=(const ExportLook&) = delete;

 private:
  QCustomPlot* p_;
  PlotLook before_;
  std::vector<std::pair<QCPTextElement*, QString>> titles_;
  std::vector<std::pair<QCPAxis*, QFont>> ticks_;
  std::vector<std::pair<QSharedPointer<QCPAxisTicker>, int>> tick_counts_;
  int legend_wrap_ = 0;
  struct GraphStyle {
    QCPGraph* graph;
    QCPScatterStyle scatter;
    QPen pen;
  };
  std::vector<GraphStyle> styles_;
  QSize legend_icon_;
  int legend_spacing_ = 0;
  static constexpr int kNarrowLayout = 600;  // layout px (3.5 in is 336)
  static constexpr double kNarrowDot = 1.0, kNarrowLine = 1.4;
};

// The PDF's creation date: from SOURCE_DATE_EPOCH (reproducible builds), else none.
std::optional<QDateTime> sourceDate() {
  bool ok = false;
  const qint64 s = qEnvironmentVariable("SOURCE_DATE_EPOCH").toLongLong(&ok);
  if (!ok || s < 0) return std::nullopt;
  return QDateTime::fromSecsSinceEpoch(s, Qt::UTC);
}

// Qt writes "/CreationDate (D:…)" with the current time. It is replaced in place by the same
// number of bytes (so the cross-reference offsets stay right): SOURCE_DATE_EPOCH's date, or
// blanks (a PDF without a creation date).
void fixCreationDate(QByteArray& pdf) {
  static const QByteArray key = "/CreationDate (";
  const auto at = pdf.indexOf(key);
  if (at < 0) return;
  const auto end = pdf.indexOf(')', at + key.size());
  if (end < 0) return;
  const auto len = end + 1 - at;
  QByteArray repl;
  if (auto d = sourceDate()) {
    repl = key + "D:" + d->toString("yyyyMMddHHmmss").toLatin1() + "Z)";
  }
  if (repl.size() > len) repl.clear();
  repl = repl.leftJustified(len, ' ');
  pdf.replace(at, len, repl);
}

// XMP metadata without the time stamps and random document id Qt would write.
QByteArray xmpMetadata(const QString& title) {
  QString dates;
  if (auto d = sourceDate()) {
    const QString iso = d->toString(Qt::ISODate);
    dates =
        QString("<xmp:CreateDate>%1</xmp:CreateDate><xmp:ModifyDate>%1</xmp:ModifyDate>").arg(iso);
  }
  return QString(
             "<?xpacket begin='' id='W5M0MpCehiHzreSzNTczkc9d'?>"
             "<x:xmpmeta xmlns:x='adobe:ns:meta/'><rdf:RDF "
             "xmlns:rdf='http://www.w3.org/1999/02/22-rdf-syntax-ns#'>"
             "<rdf:Description rdf:about='' xmlns:dc='http://purl.org/dc/elements/1.1/' "
             "xmlns:xmp='http://ns.adobe.com/xap/1.0/'>"
             "<dc:title><rdf:Alt><rdf:li xml:lang='x-default'>%1</rdf:li></rdf:Alt></dc:title>"
             "<xmp:CreatorTool>kfw</xmp:CreatorTool>%2"
             "</rdf:Description></rdf:RDF></x:xmpmeta><?xpacket end='w'?>")
      .arg(title.toHtmlEscaped(), dates)
      .toUtf8();
}

Expected<QByteArray> renderPng(QCustomPlot* plot, const ExportSpec& spec) {
  const int w = spec.layoutWidth(), h = spec.layoutHeight();
  const double s = spec.dpi / kLayoutDpi;
  QImage img(std::lround(w * s), std::lround(h * s), QImage::Format_ARGB32);
  // Text sizes resolve against the image's resolution: the layout's, while drawing.
  const int layout_dpm = static_cast<int>(std::lround(kLayoutDpi / 0.0254));
  img.setDotsPerMeterX(layout_dpm);
  img.setDotsPerMeterY(layout_dpm);
  img.fill(Qt::transparent);  // toPainter paints the plot's background
  {
    QCPPainter painter(&img);
    painter.setRenderHint(QPainter::Antialiasing);
    painter.scale(s, s);
    plot->toPainter(&painter, w, h);
  }
  const int dpm = static_cast<int>(std::lround(spec.dpi / 0.0254));
  img.setDotsPerMeterX(dpm);
  img.setDotsPerMeterY(dpm);
  QByteArray bytes;
  QBuffer buf(&bytes);
  buf.open(QIODevice::WriteOnly);
  if (!img.save(&buf, "PNG")) return failure("cannot encode the PNG");
  return bytes;
}

Expected<QByteArray> renderPdf(QCustomPlot* plot, const ExportSpec& spec) {
  QByteArray bytes;
  {
    QBuffer buf(&bytes);
    buf.open(QIODevice::WriteOnly);
    QPdfWriter pdf(&buf);
    pdf.setResolution(static_cast<int>(kLayoutDpi));  // one device pixel per layout pixel
    pdf.setPageSize(QPageSize(QSizeF(spec.width_in * 72.0, spec.height_in * 72.0), QPageSize::Point,
                              QString(), QPageSize::ExactMatch));
    pdf.setPageMargins(QMarginsF(0, 0, 0, 0));
    pdf.setCreator("kfw");
    pdf.setTitle(plot->objectName());
    pdf.setDocumentXmpMetadata(xmpMetadata(plot->objectName()));
    QCPPainter painter;
    if (!painter.begin(&pdf)) return failure("cannot start the PDF");
    painter.setMode(QCPPainter::pmVectorized);
    painter.setMode(QCPPainter::pmNoCaching);
    painter.setMode(QCPPainter::pmNonCosmetic);
    plot->toPainter(&painter, spec.layoutWidth(), spec.layoutHeight());
    if (!painter.end()) return failure("cannot finish the PDF");
  }
  fixCreationDate(bytes);
  return bytes;
}

// Qt's SVG engine writes one <text> per run of one script, each placed by Qt's own advances: a
// title with a Greek letter ("95 % χ² bounds") became three runs that a viewer, measuring the
// text with its own font metrics, drew with gaps or overlaps. Neighbouring runs on one baseline
// with the same attributes are joined into one <text>, which the viewer lays out as one string.
QByteArray joinTextRuns(const QByteArray& svg) {
  static const QRegularExpression run(
      R"re((<text ([^>]*?)x="[-0-9.e]+" y="([-0-9.e]+)"([^>]*)>)([^<]*)</text>\s*<text \2x="[-0-9.e]+" y="\3"\4>([^<]*)</text>)re");
  QString text = QString::fromUtf8(svg);
  for (;;) {
    const QString joined = QString(text).replace(run, "\\1\\5\\6</text>");
    if (joined == text) break;
    text = joined;
  }
  return text.toUtf8();
}

Expected<QByteArray> renderSvg(QCustomPlot* plot, const ExportSpec& spec) {
  const int w = spec.layoutWidth(), h = spec.layoutHeight();
  QByteArray bytes;
  QBuffer buf(&bytes);
  buf.open(QIODevice::WriteOnly);
  QSvgGenerator gen;
  gen.setOutputDevice(&buf);
  gen.setResolution(static_cast<int>(kLayoutDpi));
  gen.setSize(QSize(w, h));
  gen.setViewBox(QRect(0, 0, w, h));
  gen.setTitle(plot->objectName());
  gen.setDescription("kfw plot");
  QCPPainter painter;
  if (!painter.begin(&gen)) return failure("cannot start the SVG");
  painter.setMode(QCPPainter::pmVectorized);
  plot->toPainter(&painter, w, h);
  if (!painter.end()) return failure("cannot finish the SVG");
  return joinTextRuns(bytes);
}

}  // namespace

int ExportSpec::layoutWidth() const {
  return std::max(16, static_cast<int>(std::lround(width_in * kLayoutDpi)));
}
int ExportSpec::layoutHeight() const {
  return std::max(16, static_cast<int>(std::lround(height_in * kLayoutDpi)));
}

Status parseSize(const QString& text, double dpi, ExportSpec& spec) {
  const QString t = text.trimmed().toLower();
  if (t == "column") {
    spec.width_in = 3.5;
    spec.height_in = 2.5;
    return Ok{};
  }
  if (t == "page") {
    spec.width_in = 7.0;
    spec.height_in = 4.0;
    return Ok{};
  }
  static const QRegularExpression re(
      R"(^([0-9]*\.?[0-9]+)\s*(px|in|mm)?\s*x\s*([0-9]*\.?[0-9]+)\s*(px|in|mm)?$)");
  const auto m = re.match(t);
  const std::string bad = "--size: '" + truncate_token(text.toStdString()) +
                          "' is not WxH with a unit px, in or mm (e.g. 3.5inx2.5in, 90x60mm, "
                          "1200x700) or a named size (column, page)";
  if (!m.hasMatch()) return Error{bad};
  QString uw = m.captured(2), uh = m.captured(4);
  if (uw.isEmpty()) uw = uh.isEmpty() ? "px" : uh;
  if (uh.isEmpty()) uh = uw;
  auto inches = [dpi](double v, const QString& unit) {
    if (unit == "in") return v;
    if (unit == "mm") return v / 25.4;
    return v / dpi;
  };
  const double w = inches(m.captured(1).toDouble(), uw), h = inches(m.captured(3).toDouble(), uh);
  // 0.5 in to 40 in: a figure, not a poster wall (a 40-in PNG at 300 dpi is 12000 px wide).
  if (!(w >= 0.5 && h >= 0.5 && w <= 40.0 && h <= 40.0)) {
    return Error{"--size: '" + truncate_token(text.toStdString()) +
                 "' is outside 0.5 in to 40 in on a side (at --dpi " +
                 std::to_string(static_cast<int>(dpi)) + ")"};
  }
  // Pixels of one image: a 40 in × 40 in figure at 1 200 dpi would be 2.3 G (QImage fails on it).
  const double px = std::round(w * dpi) * std::round(h * dpi);
  if (px > static_cast<double>(limits::kMaxExportPixels)) {
    return Error{"--size: '" + truncate_token(text.toStdString()) + "' at --dpi " +
                 std::to_string(static_cast<int>(dpi)) + " is " +
                 std::to_string(static_cast<long long>(std::round(w * dpi))) + " × " +
                 std::to_string(static_cast<long long>(std::round(h * dpi))) +
                 " pixels, more than the limit of " + std::to_string(limits::kMaxExportPixels) +
                 " (docs/limits.md); lower --dpi or the size"};
  }
  spec.width_in = w;
  spec.height_in = h;
  return Ok{};
}

Expected<Theme> parseTheme(const QString& text) {
  if (text == "light") return Theme::kLight;
  if (text == "dark") return Theme::kDark;
  return Error{unknown_message("theme", text.toStdString(), {"light", "dark"}) +
               " (--theme light or dark)"};
}

Expected<QByteArray> renderPlot(QCustomPlot* plot, const QString& format, const ExportSpec& spec) {
  const ExportLook look(plot, spec);
  if (format == "png") return renderPng(plot, spec);
  if (format == "pdf") return renderPdf(plot, spec);
  if (format == "svg") return renderSvg(plot, spec);
  return Error{"unknown export format '" + format.toStdString() + "' (png, pdf, svg)"};
}

Status exportPlot(QCustomPlot* plot, const QString& path, const ExportSpec& spec) {
  auto bytes = renderPlot(plot, QFileInfo(path).suffix().toLower(), spec);
  if (!bytes) return Error{path.toStdString() + ": " + bytes.error(), bytes.err().exit_code};
  return write_file_atomic(path.toStdString(), bytes->toStdString());
}

namespace {

QByteArray imageFormat(const QString& path) {
  const QByteArray suffix = QFileInfo(path).suffix().toLower().toLatin1();
  return QImageWriter::supportedImageFormats().contains(suffix) ? suffix : QByteArray();
}

}  // namespace

Status checkScreenshotPath(const QString& path) {
  if (imageFormat(path).isEmpty()) {
    return Error{"--screenshot: " + truncate_token(path.toStdString()) +
                 ": not an image name Qt writes (end it in .png, .jpg or .bmp)"};
  }
  OutputSet out;
  return out.add(path.toStdString(), "--screenshot");
}

Status saveScreenshot(const QImage& image, const QString& path) {
  if (auto st = checkScreenshotPath(path); !st) return st;
  QByteArray bytes;
  QBuffer buffer(&bytes);
  buffer.open(QIODevice::WriteOnly);
  if (image.isNull() || !image.save(&buffer, imageFormat(path).constData())) {
    return failure(truncate_token(path.toStdString()) + ": cannot encode the screenshot");
  }
  OutputSet out;
  if (auto st = out.add(path.toStdString(), "--screenshot"); !st) return st;
  if (auto st = out.stage(path.toStdString(), bytes.toStdString()); !st) return st;
  return out.commit();
}

Expected<QStringList> parseFormats(const QString& list) {
  QStringList out;
  for (const QString& f : list.split(',', Qt::SkipEmptyParts)) {
    const QString x = f.trimmed().toLower();
    if (x != "png" && x != "pdf" && x != "svg") {
      return Error{"--format: unknown format '" + x.toStdString() + "' (png, pdf, svg)"};
    }
    if (!out.contains(x)) out << x;
  }
  if (out.isEmpty()) return Error{"--format: no format given (png, pdf, svg)"};
  return out;
}

Expected<QList<ExportItem>> selectItems(const QList<ExportItem>& items, const QStringList& wanted) {
  if (wanted.isEmpty()) return items;
  std::vector<std::string> names;
  for (const auto& i : items)
    names.push_back(i.name.toStdString());
  QList<ExportItem> out;
  for (const QString& w : wanted) {
    bool found = false;
    for (const auto& i : items) {
      if (i.name == w || i.name.startsWith(w + '.')) {
        found = true;
        bool dup = false;
        for (const auto& o : out)
          dup = dup || o.name == i.name;
        if (!dup) out << i;
      }
    }
    if (!found) {
      return Error{"--plot: " + unknown_message("plot", w.toStdString(), names) +
                   " (kfw --list-plots PRESET lists them)"};
    }
  }
  return out;
}

Expected<QStringList> exportItems(const QList<ExportItem>& items, const QString& dir,
                                  const QStringList& formats, const QString& prefix,
                                  const ExportSpec& spec) {
  if (!QDir().mkpath(dir)) return Error{dir.toStdString() + ": cannot create the directory"};
  OutputSet out;
  QStringList written;
  for (const ExportItem& item : items) {
    for (const QString& f : formats) {
      const QString path = QDir(dir).filePath(prefix + item.name + "." + f);
      if (auto st = out.add(path.toStdString(), "--export"); !st) return st.err();
      written << path;
    }
  }
  // Everything drawn before anything is written: a failure leaves the directory as it was.
  for (const ExportItem& item : items) {
    if (item.prepare) item.prepare();
    for (const QString& f : formats) {
      const QString path = QDir(dir).filePath(prefix + item.name + "." + f);
      auto bytes = renderPlot(item.plot, f, spec);
      if (!bytes) return Error{path.toStdString() + ": " + bytes.error(), bytes.err().exit_code};
      if (auto st = out.stage(path.toStdString(), bytes->toStdString()); !st) return st.err();
    }
  }
  if (auto st = out.commit(); !st) return st.err();
  return written;
}

}  // namespace kfw
