// MainWindow, per document: the parameter panel, the scenario's controls and plots made for a
// new document, each finished run drawn (plots, consistency, pins, metrics, status bar), the
// error banner, and the labels that describe the preset and the data.
#include <qcustomplot.h>

#include <QAction>
#include <QComboBox>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QGridLayout>
#include <QLabel>
#include <QPushButton>
#include <QRegularExpression>
#include <QScrollArea>
#include <QSplitter>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>

#include "consistency_panel.h"
#include "data_tab.h"
#include "draw_batch.h"
#include "main_window.h"
#include "metrics_panel.h"
#include "param_panel.h"
#include "plot_zoom.h"
#include "transport_bar.h"

namespace kfw {

namespace {
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
}  // namespace

void MainWindow::documentReplaced() {
  transport_->reset();  // the replay cursor belongs to the last document (issue 32, item 7)
  rebuildScenarioUi();
  refreshPresetList();
  clearError();
  const Preset& p = preset();
  setWindowTitle("kfw — " + q(p.title.empty() ? scenario()->title() : p.title));
  updateDescription();
}

void MainWindow::rebuildScenarioUi() {
  delete panel_;
  delete controls_;
  controls_ = nullptr;
  panel_ = new ParamPanel(scenario()->params(), preset().ranges);
  panel_->setObjectName("paramPanel");
  panel_->setValues(values());
  left_->insertWidget(left_->count() - 1, panel_);
  connect(panel_, &ParamPanel::valueChanged, this,
          [this](const QString& key, double v) { doc_->setValue(key.toStdString(), v); });
  view_->setScenario(scenario());
  controls_ = view_->createControls(nullptr);
  if (controls_) left_->insertWidget(left_->count() - 1, controls_);
  connect(view_.get(), &ScenarioView::parameterEdited, this,
          [this](const QString& key, double v) { setParam(key.toStdString(), v); });
  connect(view_.get(), &ScenarioView::idle, runs_, &RunController::drawingFinished);
  rebuildPlots();
  const QString stem = preset().path.empty() ? q(scenario()->name())
                                             : QFileInfo(q(preset().path)).completeBaseName();
  export_->setPlots(plots_, stem);
  // The plots shown when presenting are remembered per preset: every model file is the scenario
  // "model", so per scenario one file's choice was offered to all.
  present_->setScenario(stem);
  updateDataLabel();
}

void MainWindow::rebuildPlots() {
  // Plots: two columns in a scroll area; at 1366×768 the first two rows are in view.
  delete plot_host_;
  plot_host_ = new QWidget;
  auto* grid = new QGridLayout(plot_host_);
  grid->setContentsMargins(2, 2, 2, 2);
  grid->setSpacing(4);
  // Equal columns whatever the titles' lengths (a wrapped title changes a plot's size hint).
  grid->setColumnStretch(0, 1);
  grid->setColumnStretch(1, 1);
  plots_ = view_->createPlots(plot_host_);
  for (int i = 0; i < plots_.size(); ++i) {
    plots_[i].plot->setObjectName("plot." + plots_[i].name);
    // An explicit minimum: a long title's width must not widen the grid past the viewport
    // (the plots then scroll sideways and the second column is off screen at 1366×768).
    plots_[i].plot->setMinimumSize(200, 240);
    grid->addWidget(plots_[i].plot, i / 2, i % 2);
  }
  plot_area_->setWidget(plot_host_);
  zoom_ = new plot::ZoomGroup(
      plots_, [this] { replay_->redraw(); }, plot_host_);
  replay_->setView(view_.get(), plots_, zoom_);
}

plot::ZoomGroup* MainWindow::zoom() const {
  return zoom_.data();
}

void MainWindow::applyResult(std::shared_ptr<const RunResult> r, const ParamValues& v, double ms) {
  QElapsedTimer apply;
  apply.start();
  const bool moved = replay_->setResult(r);
  {
    plot::DrawBatch batch;  // the view's reductions on both cores (draw_batch.h)
    view_->setDataset(runs_->dataset());
    view_->setResult(r, v);  // draws up to the view's cursor
    if (moved) view_->setCursor(transport_->cursor());
  }
  consistency_->setResult(r);  // drawn when its tab is shown
  if (qEnvironmentVariableIsSet("KFW_TIMING")) {
    qInfo("run %.1f ms, plots %.1f ms, since request %.1f ms", ms, apply.nsecsElapsed() / 1e6,
          runs_->sinceRequestMs());
    for (const auto& p : plots_)
      qInfo("  %s replot %.1f ms", qPrintable(p.name), p.plot->replotTime());
  }
  if (doc_->pinsStale()) {
    doc_->refreshPins();
  } else {
    fillMetrics();
  }
}

void MainWindow::runApplied(bool ok) {
  if (ok) {
    // The status bar: results and warnings (a screenshot stays the same run to run); the
    // timings in its tooltip.
    const auto r = result();
    status_->setText(statusText());
    status_->setToolTip(QString("%1 steps · run %2 ms · request→plots %3 ms")
                            .arg(r->steps())
                            .arg(runs_->lastWallMs(), 0, 'f', 1)
                            .arg(runs_->lastLatencyMs(), 0, 'f', 1));
    status_->setStyleSheet(r->warnings.empty() ? QString() : QString("QLabel { color: #8a4b00; }"));
  }
  if (!runs_->settled()) return;
  // A later success clears the error banner (a run error, or one shown before the request).
  if (ok && error_->isVisible() && error_->property("fromRun").toBool()) clearError();
  emit resultApplied();
}

void MainWindow::showError(const QString& message, bool from_run) {
  last_error_ = message;
  error_->setText("⚠ " + message);
  error_->setProperty("fromRun", from_run);
  error_->show();
  emit errorShown(message);
}

void MainWindow::clearError() {
  error_->hide();
  error_->clear();
}

void MainWindow::setParam(const std::string& key, double value) {
  if (panel_) panel_->setValue(key, value);
}

std::string MainWindow::primaryParameter() const {
  if (!scenario()) return {};
  const auto& specs = scenario()->params().specs();
  for (const auto& s : specs) {
    if (s.key == "Q") return s.key;
  }
  for (const auto& s : specs) {
    if (!is_sim_key(s.key) && (s.scale == Scale::kLog || s.scale == Scale::kLinear)) return s.key;
  }
  return specs.empty() ? std::string() : specs.front().key;
}

void MainWindow::updateUndoActions() {
  if (!undo_action_) return;
  const Document* d = document();
  undo_action_->setEnabled(d && d->can_undo());
  redo_action_->setEnabled(d && d->can_redo());
  undo_action_->setText(doc_->undoText());
  redo_action_->setText(doc_->redoText());
}

void MainWindow::showPins() {
  if (view_) view_->setSnapshots(doc_->pinnedRuns(false));
  fillMetrics();
}

// The metrics table (metrics_panel.cpp): the live run and one column per snapshot.
void MainWindow::fillMetrics() {
  if (!scenario()) return;
  metrics_->setRuns(*scenario(), result(), doc_->pinnedRuns(true), primary_metric_);
  status_->setText(statusText());
  fitMetricsPanel();
}

void MainWindow::fitMetricsPanel() {
  auto* split = findChild<QSplitter*>("leftSplit");
  if (!split || metrics_split_by_user_ || split->count() != 2 || present_->presentation()) return;
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

void MainWindow::presentationChanged(bool on) {
  auto* split = findChild<QSplitter*>("leftSplit");
  if (!split || split->count() != 2) return;
  if (on && left_sizes_before_present_.isEmpty()) left_sizes_before_present_ = split->sizes();
  description_->setVisible(!on);
  if (!on) {
    if (!left_sizes_before_present_.isEmpty()) split->setSizes(left_sizes_before_present_);
    left_sizes_before_present_.clear();
    return;
  }
  // Once the new fonts have laid out: the table keeps its primary row, at most a quarter.
  QTimer::singleShot(0, this, [this, split] {
    if (!present_->presentation()) return;
    const int chrome = std::max(0, split->widget(1)->height() - metrics_->height());
    const QList<int> sizes = split->sizes();
    const int total = sizes[0] + sizes[1];
    const int metrics = std::min(metrics_->heightThrough(0) + chrome, total / 4);
    split->setSizes({total - metrics, metrics});
  });
}

void MainWindow::setPrimaryMetric(const std::string& key) {
  primary_metric_ = key;
  fillMetrics();
}

QString MainWindow::statusText() const {
  const auto r = result();
  if (!r || !scenario()) return {};
  QString msg = QString("%1 steps").arg(r->steps());
  const QString primary = metrics_->primaryKey();
  if (!primary.isEmpty()) {
    const std::string k = primary.toStdString();
    const MetricSpec spec = describe_metric(*scenario(), k, r.get());
    msg += QString(" · %1 = %2").arg(q(spec.label), MetricsPanel::format(r->metrics.at(k)));
    if (!spec.unit.empty()) msg += " " + q(spec.unit);
  }
  if (snapshotCount() > 0) msg += QString(" · %1 pinned").arg(snapshotCount());
  for (const auto& w : r->warnings)
    msg += " · ⚠ " + q(w);
  return msg;
}

QString MainWindow::presetDescription() const {
  return description_ ? description_->text() : QString();
}

void MainWindow::updateDescription() {
  QString text = q(preset().description);
  // Long descriptions: the first two sentences under the picker, the whole in the tooltip.
  description_->setToolTip(text.isEmpty() ? QString() : "<p>" + text.toHtmlEscaped() + "</p>");
  const int cut = text.indexOf(QRegularExpression("[.;] "), 0);
  if (text.size() > 220 && cut > 0) {
    const int second = text.indexOf(QRegularExpression("[.;] "), cut + 2);
    const int end = (second > 0 && second < 300) ? second : cut;
    text = text.left(end + 1) + " …";
  }
  description_->setText(text);
  description_->setVisible(!text.isEmpty());
}

// Says honestly whether the plots show the file: a file the current mode ignores is named as
// not used, with a button that sets the mode that uses it.
void MainWindow::updateDataLabel() {
  const auto file = data_->fileData();
  std::optional<Scenario::DataUnused> unused;
  if (file && document()) unused = data_->unused();
  const QString name = file ? QFileInfo(q(file->source)).fileName() : QString();
  if (file && unused) {
    data_label_->setText(QString("<b>Data:</b> %1 is loaded but <b>not used</b>: %2; the plots "
                                 "show the simulation.")
                             .arg(name, q(unused->why)));
  } else if (file) {
    QString text = QString("<b>Data:</b> %1 (%2 rows)").arg(name).arg(file->rows());
    if (!file->time_origin.empty()) text += ", t = 0 at " + q(file->time_origin);
    data_label_->setText(text);
  } else {
    data_label_->setText("<b>Data:</b> simulated from the Simulator parameters");
  }
  data_label_->setToolTip(file ? q(file->source) : QString());
  if (!data_fix_) {
    data_fix_ = new QPushButton(this);
    data_fix_->setObjectName("useDataMode");
    left_->insertWidget(left_->indexOf(data_label_) + 1, data_fix_);
    connect(data_fix_, &QPushButton::clicked, data_, &DataController::useFileMode);
  }
  data_fix_->setVisible(file && unused);
  if (unused) data_fix_->setText("Use the file: set " + q(unused->fix));
  sim_button_->setEnabled(static_cast<bool>(file));
  if (panel_) {
    const bool sim_off = file && !unused;
    panel_->setGroupEnabled("Simulator", !sim_off, sim_off ? "off: data from file" : QString());
  }
}

QComboBox* MainWindow::dataColumnCombo() const {
  return data_tab_->columnCombo();
}

QCustomPlot* MainWindow::dataPlot() const {
  return data_tab_->plot();
}

}  // namespace kfw
