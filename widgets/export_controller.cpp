#include "export_controller.h"

#include <QFileDialog>
#include <QMessageBox>

#include "consistency_panel.h"
#include "export_dialog.h"
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
  ExportDialog d(plotNames(), window_);
  if (!last_folder_.isEmpty()) d.setFolder(last_folder_);
  if (dialog_hook_) {
    if (!dialog_hook_(d)) return;
  } else if (d.exec() != QDialog::Accepted) {
    return;
  }
  const Status st = exportFromDialog(d);
  if (!st) QMessageBox::warning(window_, "Export", QString::fromStdString(st.error()));
}

Status ExportController::exportFromDialog(const ExportDialog& d) {
  if (d.folder().isEmpty()) return Error{"export: choose a folder"};
  if (d.formats().isEmpty()) return Error{"export: choose at least one format"};
  const QStringList chosen = d.chosenPlots();
  if (chosen.isEmpty()) return Error{"export: choose at least one plot"};
  auto spec = d.spec();
  if (!spec) return spec.err();
  // Every plot checked: no selection (the consistency panel's per-channel names stay whole).
  const QStringList only = chosen.size() == plotNames().size() ? QStringList() : chosen;
  auto r = exportAll(d.folder(), d.formats(), *spec, only);
  if (!r) return r.err();
  last_folder_ = d.folder();
  emit status(QString("exported %1 files to %2").arg(r->size()).arg(d.folder()));
  return Ok{};
}

}  // namespace kfw
