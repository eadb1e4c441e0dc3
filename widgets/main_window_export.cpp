// MainWindow: export of the scenario's and the consistency panel's plots (kfw --export, File →
// Export plots…) and their stable names (kfw --list-plots).
#include <QFileInfo>

#include "consistency_panel.h"
#include "main_window.h"

namespace kfw {

QList<ExportItem> MainWindow::exportedPlots() const {
  QList<ExportItem> all;
  for (const PlotPanel& p : plots_)
    all << ExportItem{p.name, p.title, p.plot, {}};
  if (result_) all << consistency_->exportItems();
  return all;
}

QStringList MainWindow::plotNames() const {
  QStringList names;
  for (const ExportItem& i : exportedPlots())
    names << i.name;
  return names;
}

Expected<QStringList> MainWindow::exportAll(const QString& dir, const QStringList& formats,
                                            const ExportSpec& spec, const QStringList& only) {
  if (!waitForRun()) return failure("export: the run did not finish");
  if (!result_) return failure("export: no result to plot (" + last_error_.toStdString() + ")");
  auto items = selectItems(exportedPlots(), only);
  if (!items) return items.err();
  // Files are named after the preset (two presets of one scenario do not overwrite each other).
  const QString stem = preset().path.empty()
                           ? QString::fromStdString(scenario_->name())
                           : QFileInfo(QString::fromStdString(preset().path)).completeBaseName();
  const int channel = consistency_->channel();
  consistency_->refresh();
  auto files = exportItems(*items, dir, formats, stem + "_", spec);
  consistency_->setChannel(channel);  // the channel the user looks at, drawn again
  consistency_->refresh();
  return files;
}

}  // namespace kfw
