#include "export_controller.h"

#include <QFileDialog>
#include <QMessageBox>

#include "consistency_panel.h"
#include "run_controller.h"

namespace kfw {

ExportController::ExportController(RunController* runs, ConsistencyPanel* consistency,
                                   QWidget* window)
    : QObject(window), runs_(runs), consistency_(consistency), window_(window) {}

void ExportController::setPlots(const QList<PlotPanel>& plots, const QString& stem) {
  plots_ = plots;
  stem_ = stem;
}

QList<ExportItem> ExportController::exportedPlots() const {
  QList<ExportItem> all;
  for (const PlotPanel& p : plots_)
    all << ExportItem{p.name, p.title, p.plot, {}};
  if (runs_->result() && consistency_) all << consistency_->exportItems();
  return all;
}

QStringList ExportController::plotNames() const {
  QStringList names;
  for (const ExportItem& i : exportedPlots())
    names << i.name;
  return names;
}

Expected<QStringList> ExportController::exportAll(const QString& dir, const QStringList& formats,
                                                  const ExportSpec& spec, const QStringList& only) {
  if (!runs_->waitSettled()) return failure("export: the run did not finish");
  if (!runs_->result()) {
    return failure("export: no result to plot (" + last_problem_.toStdString() + ")");
  }
  auto items = selectItems(exportedPlots(), only);
  if (!items) return items.err();
  // Files are named after the preset (two presets of one scenario do not overwrite each other).
  if (!consistency_) return exportItems(*items, dir, formats, stem_ + "_", spec);
  const int channel = consistency_->channel();
  consistency_->refresh();
  auto files = exportItems(*items, dir, formats, stem_ + "_", spec);
  consistency_->setChannel(channel);  // the channel the user looks at, drawn again
  consistency_->refresh();
  return files;
}

void ExportController::exportWithDialog() {
  const QString dir = QFileDialog::getExistingDirectory(window_, "Export plots to");
  if (dir.isEmpty()) return;
  auto r = exportAll(dir, {"png", "pdf", "svg"});
  if (!r) {
    QMessageBox::warning(window_, "Export", QString::fromStdString(r.error()));
  } else {
    emit status(QString("exported %1 files to %2").arg(r->size()).arg(dir));
  }
}

}  // namespace kfw
