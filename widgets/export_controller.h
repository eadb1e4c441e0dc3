// Export of the window's plots: the scenario view's plots, then the consistency panel's per
// channel, in every format asked for, all or nothing, files named <preset>_<plot>.<format>
// (kfw --export, File → Export plots…), and their stable names (kfw --list-plots).
#pragma once

#include <QList>
#include <QObject>
#include <QPointer>
#include <QString>
#include <QStringList>
#include <functional>

#include "core/expected.h"
#include "plot_export.h"
#include "scenario_view.h"

class QWidget;

namespace kfw {

class ConsistencyPanel;
class ExportDialog;
class RunController;

class ExportController : public QObject {
  Q_OBJECT
 public:
  // Exports wait for `runs` to settle; `consistency` (may be null) adds its plots once a run
  // has a result. `window`: the parent of the controller and of its dialogs.
  ExportController(RunController* runs, ConsistencyPanel* consistency, QWidget* window = nullptr);

  // The scenario view's plots, and the stem their files are named after (the preset's name).
  void setPlots(const QList<PlotPanel>& plots, const QString& stem);
  // What an export writes: the scenario's plots, then the consistency panel's per channel.
  QList<ExportItem> exportedPlots() const;
  QStringList plotNames() const;
  // Every plot (or those named in `only`) in every format into `dir`, all or nothing.
  Expected<QStringList> exportAll(const QString& dir, const QStringList& formats,
                                  const ExportSpec& spec = {}, const QStringList& only = {});
  // File → Export plots…: the folder, plots, formats, size, dpi, text scale and theme chosen in
  // a dialog (export_dialog.h: what kfw --export takes); the outcome in a message box or
  // status(). Tests set a hook that fills the dialog instead of showing it (false: cancelled).
  void exportWithDialog();
  Status exportFromDialog(const ExportDialog& d);
  void setDialogHook(std::function<bool(ExportDialog&)> hook) { dialog_hook_ = std::move(hook); }

 public slots:
  // The last problem the window showed: named when there is no result to export.
  void noteProblem(const QString& message) { last_problem_ = message; }

 signals:
  void status(const QString& message);

 private:
  RunController* runs_;
  QPointer<ConsistencyPanel> consistency_;
  QWidget* window_;
  QList<PlotPanel> plots_;
  QString stem_;
  QString last_problem_;
  QString last_folder_;
  std::function<bool(ExportDialog&)> dialog_hook_;
};

}  // namespace kfw
