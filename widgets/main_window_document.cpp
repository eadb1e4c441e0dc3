// MainWindow, the document side: datasets and their mappings, sessions, presets, undo/redo,
// snapshots and the metrics table. Everything here goes through the engine's Document.
#include <QColor>
#include <QCryptographicHash>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QSettings>
#include <QSplitter>
#include <QTimer>
#include <algorithm>
#include <cmath>

#include "document/workspace.h"
#include "main_window.h"
#include "metrics_panel.h"
#include "param_panel.h"
#include "run_controller.h"

namespace kfw {

namespace {
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
}  // namespace

void MainWindow::pinSnapshot(const QString& name) {
  if (!result_ || !scenario_) return;
  Snapshot snap{name.toStdString(), values()};
  doc_->add_snapshot(snap);
  snapshots_.push_back({snap, result_, runner_->dataset()});
  updateUndoActions();
  refreshSnapshots();
}

void MainWindow::clearSnapshots() {
  if (doc_) doc_->clear_snapshots();
  snapshots_.clear();
  updateUndoActions();
  refreshSnapshots();
}

bool MainWindow::undo() {
  if (!doc_ || !doc_->undo()) return false;
  syncFromDocument();
  return true;
}

bool MainWindow::redo() {
  if (!doc_ || !doc_->redo()) return false;
  syncFromDocument();
  return true;
}

void MainWindow::syncFromDocument() {
  if (!doc_) return;
  panel_->setValues(doc_->values());
  if (doc_->data() != loaded_data_) {
    if (!doc_->data()) {
      file_data_.reset();
    } else {
      auto ds = load_dataset_file(*scenario_, doc_->data()->path, doc_->data()->mapping);
      if (ds) {
        file_data_ = std::make_shared<const Dataset>(std::move(*ds));
      } else {
        showError(q(ds.error()));
      }
    }
    loaded_data_ = doc_->data();
    runner_->setFileDataset(file_data_);
    updateDataLabel();
  }
  // Keep the runs of snapshots that are still there; re-run the ones that came back.
  std::vector<Pinned> next;
  for (const auto& snap : doc_->snapshots()) {
    Pinned p{snap, nullptr, nullptr};
    for (const auto& old : snapshots_) {
      if (old.snap == snap) p = old;
    }
    next.push_back(std::move(p));
  }
  snapshots_ = std::move(next);
  refreshSnapshots();
  updateUndoActions();
  requestRun();
}

void MainWindow::updateUndoActions() {
  if (!undo_action_) return;
  const bool has = static_cast<bool>(doc_);
  undo_action_->setEnabled(has && doc_->can_undo());
  redo_action_->setEnabled(has && doc_->can_redo());
  undo_action_->setText(has && doc_->can_undo() ? "&Undo " + q(doc_->undo_label()) : "&Undo");
  redo_action_->setText(has && doc_->can_redo() ? "&Redo " + q(doc_->redo_label()) : "&Redo");
}

// Re-runs stale snapshots on the current dataset (synchronously: a few ms each), then redraws
// the ghosts and the metrics columns.
void MainWindow::refreshSnapshots() {
  const auto current = runner_->dataset();
  for (auto& p : snapshots_) {
    if (current && p.data != current) {
      auto r = scenario_->run(*current, p.snap.values);
      p.result = r ? *r : nullptr;
      p.data = current;
    }
  }
  ScenarioView::Snapshots ghosts;
  for (const auto& p : snapshots_) {
    if (p.result) ghosts.append({q(p.snap.name), p.result});
  }
  if (view_) view_->setSnapshots(ghosts);
  fillMetrics();
}

// The metrics table (metrics_panel.cpp): the live run and one column per snapshot.
void MainWindow::fillMetrics() {
  if (!scenario_) return;
  MetricsPanel::Columns cols;
  for (const auto& p : snapshots_)
    cols.append({q(p.snap.name), p.result});
  metrics_->setRuns(*scenario_, result_, cols, primary_metric_);
  status_->setText(statusText());
  fitMetricsPanel();
}

void MainWindow::resizeEvent(QResizeEvent* event) {
  QMainWindow::resizeEvent(event);
  QTimer::singleShot(0, this, [this] { fitMetricsPanel(); });
}

void MainWindow::fitMetricsPanel() {
  auto* split = findChild<QSplitter*>("leftSplit");
  if (!split || metrics_split_by_user_ || split->count() != 2) return;
  if (!split->property("kfwWatched").toBool()) {  // splitterMoved: the user's drags only
    split->setProperty("kfwWatched", true);
    connect(split, &QSplitter::splitterMoved, this, [this] { metrics_split_by_user_ = true; });
  }
  // The table's rows, plus what its pane holds around it (a title, margins).
  const int chrome = std::max(0, split->widget(1)->height() - metrics_->height());
  const int need = metrics_->heightThrough(metrics_->primaryGroupEnd()) + chrome;
  QList<int> sizes = split->sizes();
  const int total = sizes[0] + sizes[1];
  if (total <= 0 || sizes[1] >= need) return;
  // The parameters keep at least 40 % (they scroll); the table gets the rest it needs.
  const int metrics = std::min(need, total - total * 2 / 5);
  split->setSizes({total - metrics, metrics});
}

void MainWindow::setPrimaryMetric(const std::string& key) {
  primary_metric_ = key;
  fillMetrics();
}

QString MainWindow::statusText() const {
  if (!result_ || !scenario_) return {};
  QString msg = QString("%1 steps").arg(result_->steps());
  const QString primary = metrics_->primaryKey();
  if (!primary.isEmpty()) {
    const std::string k = primary.toStdString();
    const MetricSpec spec = describe_metric(*scenario_, k, result_.get());
    msg += QString(" · %1 = %2").arg(q(spec.label), MetricsPanel::format(result_->metrics.at(k)));
    if (!spec.unit.empty()) msg += " " + q(spec.unit);
  }
  if (!snapshots_.empty()) msg += QString(" · %1 pinned").arg(snapshots_.size());
  for (const auto& w : result_->warnings)
    msg += " · ⚠ " + q(w);
  return msg;
}

void MainWindow::resetToPreset() {
  if (!doc_) return;
  doc_->reset_to_preset();  // one undo step; the snapshots stay
  syncFromDocument();
}

QString MainWindow::viewState() const {
  // Geometry and splitters, then each registered part (zoom, replay, ...) under its own key.
  QJsonObject o;
  o["geometry"] = QString::fromLatin1(saveGeometry().toBase64());
  QJsonObject splits;
  for (auto* sp : findChildren<QSplitter*>()) {
    if (!sp->objectName().isEmpty()) {
      splits[sp->objectName()] = QString::fromLatin1(sp->saveState().toBase64());
    }
  }
  o["splitters"] = splits;
  for (const auto& part : view_parts_)
    o[part.key] = part.save();
  return QString::fromUtf8(QJsonDocument(o).toJson(QJsonDocument::Compact));
}

void MainWindow::restoreViewState(const QString& state) {
  auto restoreSplit = [this](const QString& name, const QString& b64) {
    if (auto* sp = findChild<QSplitter*>(name))
      sp->restoreState(QByteArray::fromBase64(b64.toLatin1()));
  };
  if (!state.startsWith('{')) {
    // Sessions before the JSON form: geometry, then two splitters, base64, ':'-separated.
    const QStringList parts = state.split(':');
    if (!parts.isEmpty() && !parts[0].isEmpty()) {
      restoreGeometry(QByteArray::fromBase64(parts[0].toLatin1()));
    }
    const char* splits[] = {"mainSplit", "leftSplit"};
    for (int i = 1; i < parts.size() && i <= 2; ++i)
      restoreSplit(splits[i - 1], parts[i]);
    return;
  }
  const QJsonObject o = QJsonDocument::fromJson(state.toUtf8()).object();
  if (o.contains("geometry")) {
    restoreGeometry(QByteArray::fromBase64(o["geometry"].toString().toLatin1()));
  }
  const QJsonObject splits = o["splitters"].toObject();
  for (auto it = splits.begin(); it != splits.end(); ++it)
    restoreSplit(it.key(), it.value().toString());
  for (const auto& part : view_parts_) {
    if (o.contains(part.key)) part.restore(o[part.key]);
  }
}

void MainWindow::addViewStatePart(const QString& key, std::function<QJsonValue()> save,
                                  std::function<void(const QJsonValue&)> restore) {
  view_parts_.push_back({key, std::move(save), std::move(restore)});
}

Status MainWindow::saveSession(const QString& path) const {
  if (!doc_) return Error{"nothing to save"};
  Session s = doc_->to_session();
  s.window_state = viewState().toStdString();
  if (auto st = save_session(path.toStdString(), s); !st) return st;
  doc_->mark_saved();
  return Ok{};
}

Status MainWindow::loadSession(const QString& path) {
  auto s = load_session(path.toStdString());
  if (!s) return s.err();
  auto doc = Document::from_session(*s, path.toStdString());
  if (!doc) return doc.err();
  QString warning;
  if (s->data_path) {
    auto h = file_hash(*s->data_path);
    if (h && !s->data_hash.empty() && *h != s->data_hash) {
      warning = q(*s->data_path) + " changed since the session was saved (hash differs)";
    }
  }
  doc->mark_saved();
  if (auto st = adoptDocument(std::move(*doc)); !st) return st;
  waitForRun();
  refreshSnapshots();
  restoreViewState(QString::fromStdString(s->window_state));
  if (!warning.isEmpty()) showError(warning);
  return Ok{};
}

void MainWindow::useSimulatedData() {
  if (!file_data_) return;
  file_data_.reset();
  loaded_data_.reset();
  doc_->set_data(std::nullopt);
  updateUndoActions();
  runner_->setFileDataset(nullptr);
  updateDataLabel();
  requestRun();
}

void MainWindow::setParam(const std::string& key, double value) {
  if (panel_) panel_->setValue(key, value);
}

Status MainWindow::savePreset(const QString& path) const {
  if (!doc_) return Error{"nothing to save"};
  Preset p = doc_->preset();
  p.values = values();
  if (doc_->data()) {
    p.data_path = doc_->data()->path;
    p.mapping = doc_->data()->mapping;
  } else {
    p.data_path.reset();
  }
  return save_preset(path.toStdString(), p);
}

}  // namespace kfw
