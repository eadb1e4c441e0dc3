#include "plot_export.h"

#include <qcustomplot.h>

#include <QDir>
#include <QFileInfo>
#include <QSvgGenerator>

#include "plot_kit.h"

namespace kfw {

namespace {
// Exports are drawn antialiased with vector dots; the on-screen look comes back afterwards.
class ExportLook {
 public:
  explicit ExportLook(QCustomPlot* p) : p_(p) { plot::setExportLook(p_, true); }
  ~ExportLook() {
    plot::setExportLook(p_, false);
    p_->replot(QCustomPlot::rpQueuedReplot);
  }
  ExportLook(const ExportLook&) = delete;
  ExportLook& operator=(const ExportLook&) = delete;

 private:
  QCustomPlot* p_;
};
}  // namespace

Status exportPlot(QCustomPlot* plot, const QString& path, int width, int height) {
  const QString ext = QFileInfo(path).suffix().toLower();
  const ExportLook look(plot);
  bool ok = false;
  if (ext == "png") {
    ok = plot->savePng(path, width, height, 1.0, -1, 96);
  } else if (ext == "pdf") {
    ok = plot->savePdf(path, width, height, QCP::epNoCosmetic, "kfw", plot->objectName());
  } else if (ext == "svg") {
    QSvgGenerator gen;
    gen.setFileName(path);
    gen.setSize(QSize(width, height));
    gen.setViewBox(QRect(0, 0, width, height));
    gen.setTitle(plot->objectName());
    gen.setDescription("kfw plot");
    QCPPainter painter;
    if (painter.begin(&gen)) {
      plot->toPainter(&painter, width, height);
      ok = painter.end();
    }
  } else {
    return Error{path.toStdString() + ": unknown export format '" + ext.toStdString() + "'"};
  }
  if (!ok) return Error{path.toStdString() + ": could not write the file"};
  return Ok{};
}

Expected<QStringList> parseFormats(const QString& list) {
  QStringList out;
  for (const QString& f : list.split(',', Qt::SkipEmptyParts)) {
    const QString x = f.trimmed().toLower();
    if (x != "png" && x != "pdf" && x != "svg") {
      return Error{"--format: unknown format '" + x.toStdString() + "' (png, pdf, svg)"};
    }
    out << x;
  }
  if (out.isEmpty()) return Error{"--format: no format given (png, pdf, svg)"};
  return out;
}

Expected<QStringList> exportPanels(const QList<PlotPanel>& panels, const QString& dir,
                                   const QStringList& formats, const QString& prefix) {
  if (!QDir().mkpath(dir)) return Error{dir.toStdString() + ": cannot create the directory"};
  QStringList written;
  for (const PlotPanel& p : panels) {
    for (const QString& f : formats) {
      const QString path = QDir(dir).filePath(prefix + p.name + "." + f);
      if (auto st = exportPlot(p.plot, path); !st) return st.err();
      written << path;
    }
  }
  return written;
}

}  // namespace kfw
