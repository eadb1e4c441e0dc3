// The main window's tuning side: the Tune and Sweep dialogs, whose results (a tuning, its
// revert, a clicked sweep point) each go on the document's undo stack, the tuning set kept in
// the document, and the question before unsaved work or snapshots are thrown away.
#include <QCloseEvent>
#include <QFileInfo>
#include <QMessageBox>

#include "experiment/tuning.h"
#include "main_window.h"
#include "param_panel.h"
#include "run_controller.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw {

void MainWindow::applyValuesAs(const ParamValues& values, const QString& label) {
  if (!panel_ || !doc_) return;
  if (auto st = doc_->set_values(values, label.toStdString()); !st) {
    showError(QString::fromStdString(st.error()));
    return;
  }
  panel_->setValues(doc_->values());
  updateUndoActions();
  requestRun();
}

TuneDialog* MainWindow::openTuneDialog() {
  if (!scenario_ || !doc_ || !waitForRun() || !runner_->dataset()) return nullptr;
  const QString name = doc_->data()
                           ? QFileInfo(QString::fromStdString(doc_->data()->path)).fileName()
                           : QString("simulated");
  auto* d = new TuneDialog(doc_->preset(), runner_->dataset(), name, result_, values(), this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  // The document's tuning set comes back with the dialog (files that no longer read are skipped
  // with their message).
  for (const auto& ref : doc_->tuning_set()) {
    if (auto st = d->addLog(QString::fromStdString(ref.path)); !st) {
      showError(QString::fromStdString(st.error()));
    }
  }
  connect(d, &TuneDialog::tuned, this, [this, d](const ParamValues& v) {
    // The tuned objective's metric goes first in the metrics table (rmse+nis ranks rmse).
    if (auto obj = make_objective(*scenario_, d->objective().toStdString(), result_.get())) {
      primary_metric_ = obj->spec.key;
    }
    applyValuesAs(v, "tune");
  });
  connect(d, &TuneDialog::reverted, this,
          [this](const ParamValues& v) { applyValuesAs(v, "revert tuning"); });
  connect(d, &TuneDialog::tuningSetChanged, this, [this](const QStringList& paths) {
    std::vector<DataRef> logs;
    for (const auto& p : paths)
      logs.push_back({p.toStdString(), doc_->preset().mapping});
    doc_->set_tuning_set(std::move(logs));
    updateUndoActions();
  });
  d->show();
  return d;
}

SweepDialog* MainWindow::openSweepDialog() {
  if (!scenario_ || !waitForRun() || !runner_->dataset() || !result_) return nullptr;
  auto* d = new SweepDialog(scenario_, runner_->dataset(), values(), result_->metrics, this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  connect(d, &SweepDialog::pointChosen, this,
          [this](const ParamValues& v) { applyValuesAs(v, "sweep point"); });
  d->show();
  return d;
}

bool MainWindow::confirmDiscard(const QString& action) {
  if (!doc_ || (!doc_->dirty() && doc_->snapshots().empty())) return true;
  QString what;
  if (doc_->dirty()) what = "unsaved changes";
  if (!doc_->snapshots().empty()) {
    what +=
        QString(what.isEmpty() ? "" : " and ") + QString("%1 pinned snapshot%2")
                                                     .arg(doc_->snapshots().size())
                                                     .arg(doc_->snapshots().size() == 1 ? "" : "s");
  }
  const QString question = QString("%1: discard %2?").arg(action, what);
  if (confirm_) return confirm_(question);
  return QMessageBox::question(this, action, question, QMessageBox::Discard | QMessageBox::Cancel,
                               QMessageBox::Cancel) == QMessageBox::Discard;
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (confirmDiscard("Quit")) {
    saveWindowSize();
    event->accept();
  } else {
    event->ignore();
  }
}

}  // namespace kfw
