#include "main_window.h"

#include <qcustomplot.h>

#include <QApplication>
#include <QCoreApplication>
#include <QCryptographicHash>
#include <QDeadlineTimer>
#include <QDir>
#include <QEventLoop>
#include <QFileDialog>
#include <QFileInfo>
#include <QGridLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <cmath>

#include "consistency_panel.h"
#include "core/statistics.h"
#include "document/workspace.h"
#include "draw_batch.h"
#include "metrics_panel.h"
#include "monte_carlo_dialog.h"
#include "param_panel.h"
#include "plot_export.h"
#include "plot_zoom.h"
#include "run_controller.h"
#include "sweep_dialog.h"
#include "transport_bar.h"
#include "tune_dialog.h"

namespace kfw {

namespace {
const ParamValues kEmpty;
const Preset kNoPreset;
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setWindowTitle("kfw — Kalman filter tuning workbench");
  runner_ = new RunController(this);
  addViewStatePart(
      "zoom", [this] { return zoom_ ? zoom_->save() : QJsonValue(); },
      [this](const QJsonValue& v) {
        if (zoom_) zoom_->restore(v);
      });
  connect(runner_, &RunController::finished, this, &MainWindow::applyResult);
  connect(runner_, &RunController::failed, this, [this](const QString& m) {
    applied_latest_ = !runner_->busy();
    showError(m, true);
    if (applied_latest_) emit resultApplied();
  });

  auto* left_host = new QWidget;
  left_ = new QVBoxLayout(left_host);
  left_->setContentsMargins(4, 4, 4, 4);
  presets_ = new QComboBox;
  presets_->setObjectName("presets");
  presets_->setToolTip("Presets in " + q(preset_dir()));
  left_->addWidget(new QLabel("<b>Preset</b>"));
  left_->addWidget(presets_);
  description_ = new QLabel;
  description_->setObjectName("presetDescription");
  description_->setWordWrap(true);
  description_->setTextFormat(Qt::PlainText);
  description_->setStyleSheet("QLabel { color: #444; }");
  left_->addWidget(description_);
  connect(presets_, &QComboBox::activated, this, [this](int i) {
    const QString path = presets_->itemData(i).toString();
    // The preset already open: back to its values (pinned snapshots stay, one undo step).
    if (doc_ && !preset().path.empty() &&
        QFileInfo(path).absoluteFilePath() == QFileInfo(q(preset().path)).absoluteFilePath()) {
      resetToPreset();
      return;
    }
    if (!confirmDiscard("Switch preset")) {
      refreshPresetList();
      return;
    }
    if (auto st = loadPreset(path); !st) {
      QMessageBox::warning(this, "Preset", q(st.error()));
      refreshPresetList();
    }
  });
  data_label_ = new QLabel;
  data_label_->setObjectName("dataLabel");
  data_label_->setWordWrap(true);
  left_->addWidget(data_label_);
  auto* data_row = new QHBoxLayout;
  auto* open_csv = new QPushButton("Open CSV…");
  open_csv->setObjectName("openCsv");
  sim_button_ = new QPushButton("Use simulated data");
  sim_button_->setObjectName("useSimulated");
  data_row->addWidget(open_csv);
  data_row->addWidget(sim_button_);
  left_->addLayout(data_row);
  connect(open_csv, &QPushButton::clicked, this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open dataset", QString(), "CSV (*.csv);;All files (*)");
    if (f.isEmpty()) return;
    if (auto st = openDataset(f); !st) QMessageBox::warning(this, "Open CSV", q(st.error()));
  });
  connect(sim_button_, &QPushButton::clicked, this, &MainWindow::useSimulatedData);
  auto* tool_row = new QHBoxLayout;
  auto* tune = new QPushButton("Tune…");
  tune->setObjectName("tuneButton");
  tune->setToolTip("Search Q, R, … for the best RMSE / likelihood / NIS consistency");
  auto* sweep = new QPushButton("Sweep…");
  sweep->setObjectName("sweepButton");
  sweep->setToolTip("Plot any metric over one or two parameters");
  auto* pin = new QPushButton("Pin");
  pin->setObjectName("pinButton");
  pin->setToolTip("Keep the current tuning, under a name, as a ghost and a metrics column");
  auto* reset = new QPushButton("Reset");
  reset->setObjectName("resetButton");
  reset->setToolTip("Back to the preset's values (one undo step; pinned snapshots stay)");
  tool_row->addWidget(tune);
  tool_row->addWidget(sweep);
  tool_row->addWidget(pin);
  tool_row->addWidget(reset);
  connect(reset, &QPushButton::clicked, this, &MainWindow::resetToPreset);
  connect(pin, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString name =
        QInputDialog::getText(this, "Pin snapshot", "Name of this tuning:", QLineEdit::Normal,
                              QString("snapshot %1").arg(snapshots_.size() + 1), &ok);
    if (ok && !name.trimmed().isEmpty()) pinSnapshot(name.trimmed());
  });
  left_->addLayout(tool_row);
  connect(tune, &QPushButton::clicked, this, [this] { openTuneDialog(); });
  connect(sweep, &QPushButton::clicked, this, [this] { openSweepDialog(); });
  // The panel and scenario controls are inserted here by rebuildScenarioUi().
  left_->addStretch(0);
  metrics_ = new MetricsPanel;

  auto* left_scroll = new QScrollArea;
  left_scroll->setWidget(left_host);
  left_scroll->setWidgetResizable(true);
  left_scroll->setMinimumWidth(340);
  auto* left_split = new QSplitter(Qt::Vertical);
  left_split->setObjectName("leftSplit");
  left_split->addWidget(left_scroll);
  left_split->addWidget(metrics_);
  left_split->setStretchFactor(0, 3);
  left_split->setStretchFactor(1, 2);

  plot_area_ = new QScrollArea;
  plot_area_->setWidgetResizable(true);
  auto* center = new QWidget;
  auto* cl = new QVBoxLayout(center);
  cl->setContentsMargins(0, 0, 0, 0);
  error_ = new QLabel;
  error_->setObjectName("errorBanner");
  error_->setWordWrap(true);
  error_->setStyleSheet("QLabel { background: #fde2e1; color: #8a1c13; padding: 6px; }");
  error_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  error_->hide();
  cl->addWidget(error_);
  auto* tabs = new QTabWidget;
  tabs->setObjectName("tabs");
  tabs->addTab(plot_area_, "Plots");
  consistency_ = new ConsistencyPanel;
  consistency_->setObjectName("consistency");
  tabs->addTab(consistency_, "Consistency");
  buildDataTab(tabs);  // main_window_data.cpp
  cl->addWidget(tabs, 1);
  transport_ = new TransportBar;
  transport_->setObjectName("transport");
  cl->addWidget(transport_);
  connect(transport_, &TransportBar::cursorChanged, this, [this](std::size_t i) {
    plot::DrawBatch batch;  // a replay frame: reductions on both cores
    if (view_) view_->setCursor(i);
  });

  auto* split = new QSplitter(Qt::Horizontal);
  split->setObjectName("mainSplit");
  split->addWidget(left_split);
  split->addWidget(center);
  split->setStretchFactor(1, 1);
  split->setSizes({380, 1220});
  setCentralWidget(split);
  status_ = new QLabel;
  status_->setObjectName("status");
  statusBar()->addWidget(status_, 1);
  buildMenus();
  buildDataMenu();  // main_window_data.cpp
  buildViewMenu();  // main_window_present.cpp
  buildHelpMenu();  // main_window_help.cpp (last: Help is the right-most menu)
  setupReplay();    // main_window_replay.cpp
  refreshPresetList();
  fitToScreen();
}

MainWindow::~MainWindow() = default;

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("Open &preset…", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open preset", q(preset_dir()), "Presets (*.json)");
    if (f.isEmpty() || !confirmDiscard("Open preset")) return;
    if (auto st = loadPreset(f); !st) QMessageBox::warning(this, "Open preset", q(st.error()));
  });
  file->addAction("&Open CSV…", QKeySequence::Open, this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open dataset", QString(), "CSV (*.csv);;All files (*)");
    if (f.isEmpty()) return;
    if (auto st = openDataset(f); !st) QMessageBox::warning(this, "Open CSV", q(st.error()));
  });
  file->addAction("Use &simulated data", this, &MainWindow::useSimulatedData);
  file->addAction("&Save preset as…", QKeySequence::SaveAs, this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save preset", QString(), "Presets (*.json)");
    if (f.isEmpty()) return;
    if (auto st = savePreset(f); !st) QMessageBox::warning(this, "Save preset", q(st.error()));
  });
  file->addAction("Open s&ession…", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open session", QString(), "Sessions (*.json)");
    if (f.isEmpty() || !confirmDiscard("Open session")) return;
    if (auto st = loadSession(f); !st) QMessageBox::warning(this, "Open session", q(st.error()));
  });
  file->addAction("Save session &as…", this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save session", "session.json", "Sessions (*.json)");
    if (f.isEmpty()) return;
    if (auto st = saveSession(f); !st) QMessageBox::warning(this, "Save session", q(st.error()));
  });
  file->addAction("&Export plots…", this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "Export plots to");
    if (dir.isEmpty()) return;
    auto r = exportAll(dir, {"png", "pdf", "svg"});
    if (!r) {
      QMessageBox::warning(this, "Export", q(r.error()));
    } else {
      status_->setText(QString("exported %1 files to %2").arg(r->size()).arg(dir));
    }
  });
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);
  QMenu* edit = menuBar()->addMenu("&Edit");
  undo_action_ = edit->addAction("&Undo", QKeySequence::Undo, this, [this] { undo(); });
  undo_action_->setObjectName("undoAction");
  redo_action_ = edit->addAction("&Redo", QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), this,
                                 [this] { redo(); });
  redo_action_->setObjectName("redoAction");
  edit->addSeparator();
  edit->addAction("Reset to &preset values", this, &MainWindow::resetToPreset);
  updateUndoActions();
  QMenu* tools = menuBar()->addMenu("&Tools");
  tools->addAction("Auto-&tune…", this, [this] { openTuneDialog(); });
  tools->addAction("&Sweep a metric…", this, [this] { openSweepDialog(); });
  tools->addAction("&Monte Carlo over seeds…", this, [this] {
    if (!scenario_) return;
    if (file_data_) {  // seeds simulate; the Simulator group is off for data from a file
      QMessageBox::information(this, "Monte Carlo",
                               "Monte Carlo simulates each seed: use "
                               "simulated data (File → Use simulated data).");
      return;
    }
    auto* d = new MonteCarloDialog(scenario_, values(), this);
    d->setAttribute(Qt::WA_DeleteOnClose);
    d->show();
  });
  tools->addAction("&Pin snapshot…", this, [this] {
    bool ok = false;
    const QString name =
        QInputDialog::getText(this, "Pin snapshot", "Name:", QLineEdit::Normal,
                              QString("snapshot %1").arg(snapshots_.size() + 1), &ok);
    if (ok && !name.isEmpty()) pinSnapshot(name);
  });
  tools->addAction("&Clear snapshots", this, &MainWindow::clearSnapshots);
  // The replay keys (Space, ←, →, Home, End) work with any focus but text entry:
  // main_window_replay.cpp; the menu names them.
  QMenu* replay = menuBar()->addMenu("&Replay");
  replay->addAction("&Play / pause\tSpace", this, [this] { transport_->togglePlay(); });
  replay->addAction("Step &back\t←", this, [this] { transport_->stepBy(-1); });
  replay->addAction("Step &forward\t→", this, [this] { transport_->stepBy(1); });
  replay->addAction("To the &start\tHome", this, [this] { transport_->seek(0); });
  replay->addAction("To the &end\tEnd", this,
                    [this] { transport_->seek(static_cast<std::size_t>(-1)); });
  replay->addAction("Show &all", this, [this] { transport_->setShowAll(true); });
}

void MainWindow::refreshPresetList() {
  const QSignalBlocker b(presets_);
  presets_->clear();
  // The built-in scenarios' presets, then the model library (presets/models/) beside them.
  const QDir dir(q(preset_dir()));
  for (const QFileInfo& f : dir.entryInfoList({"*.json"}, QDir::Files, QDir::Name)) {
    presets_->addItem(f.completeBaseName(), f.absoluteFilePath());
  }
  const QDir models(dir.filePath("models"));
  for (const QFileInfo& f : models.entryInfoList({"*.json"}, QDir::Files, QDir::Name)) {
    presets_->addItem("models/" + f.completeBaseName(), f.absoluteFilePath());
  }
  const Preset& current = preset();
  if (!current.path.empty()) {
    const int i = presets_->findData(QFileInfo(q(current.path)).absoluteFilePath());
    if (i >= 0) {
      presets_->setCurrentIndex(i);
    } else {
      presets_->addItem(QFileInfo(q(current.path)).completeBaseName(), q(current.path));
      presets_->setCurrentIndex(presets_->count() - 1);
    }
  }
}

Status MainWindow::loadPreset(const QString& preset, const std::optional<QString>& data_file,
                              const QStringList& assignments) {
  std::vector<std::string> sets;
  for (const auto& a : assignments)
    sets.push_back(a.toStdString());
  std::optional<std::string> d;
  if (data_file) d = data_file->toStdString();
  auto doc = Document::open(preset.toStdString(), d, sets);
  if (!doc) return doc.err();
  return adoptDocument(std::move(*doc));
}

const Preset& MainWindow::preset() const {
  return doc_ ? doc_->preset() : kNoPreset;
}

// Everything a new document needs before it is shown: its dataset read, its plots made. On
// failure nothing changes.
Status MainWindow::adoptDocument(Document doc) {
  std::shared_ptr<const Dataset> file;
  if (doc.data()) {
    auto ds = load_dataset_file(doc.scenario(), doc.data()->path, doc.data()->mapping);
    if (!ds) return ds.err();
    file = std::make_shared<const Dataset>(std::move(*ds));
  }
  auto view = views().make(doc.scenario().name());
  if (!view) return Error{"no plots registered for scenario '" + doc.scenario().name() + "'"};
  doc_ = std::make_unique<Document>(std::move(doc));
  scenario_ = doc_->scenario_ptr();
  file_data_ = file;
  loaded_data_ = doc_->data();
  view_ = std::move(view);
  result_.reset();
  snapshots_.clear();
  for (const auto& snap : doc_->snapshots())
    snapshots_.push_back({snap, nullptr, nullptr});
  runner_->setScenario(scenario_);
  runner_->setFileDataset(file_data_);
  rebuildScenarioUi();
  refreshPresetList();
  clearError();
  const Preset& p = doc_->preset();
  setWindowTitle("kfw — " + q(p.title.empty() ? scenario_->title() : p.title));
  updateDescription();
  updateUndoActions();
  requestRun();
  return Ok{};
}

plot::ZoomGroup* MainWindow::zoom() const {
  return zoom_.data();
}

void MainWindow::rebuildScenarioUi() {
  delete panel_;
  delete controls_;
  controls_ = nullptr;
  panel_ = new ParamPanel(scenario_->params(), doc_->preset().ranges);
  panel_->setObjectName("paramPanel");
  panel_->setValues(doc_->values());
  left_->insertWidget(left_->count() - 1, panel_);
  connect(panel_, &ParamPanel::valueChanged, this, [this](const QString& key, double v) {
    // Changes of one key in quick succession (a slider drag) are one undo step.
    const std::string k = key.toStdString();
    const bool drag = k == last_edit_key_ && last_edit_.isValid() && last_edit_.elapsed() < 800;
    last_edit_key_ = k;
    last_edit_.start();
    if (auto st = doc_->set_value(k, v, drag ? UndoMerge::kMergeSameKey : UndoMerge::kNewStep);
        !st) {
      showError(q(st.error()));
      panel_->setValues(doc_->values());
      return;
    }
    updateUndoActions();
    requestRun();
  });
  view_->setScenario(scenario_);
  controls_ = view_->createControls(nullptr);
  if (controls_) left_->insertWidget(left_->count() - 1, controls_);
  connect(view_.get(), &ScenarioView::parameterEdited, this,
          [this](const QString& key, double v) { setParam(key.toStdString(), v); });

  // Plots: two columns in a scroll area; at 1366×768 the first two rows are in view.
  delete plot_host_;
  plot_host_ = new QWidget;
  auto* grid = new QGridLayout(plot_host_);
  grid->setContentsMargins(2, 2, 2, 2);
  grid->setSpacing(4);
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
      plots_,
      [this] {
        plot::DrawBatch batch;
        if (view_ && result_) view_->setCursor(transport_->cursor());
      },
      plot_host_);
  updateDataLabel();
}

void MainWindow::applyValues(const ParamValues& values) {
  if (!panel_ || !doc_) return;
  if (auto st = doc_->set_values(values, "apply values"); !st) {
    showError(q(st.error()));
    return;
  }
  panel_->setValues(doc_->values());
  updateUndoActions();
  requestRun();
}

const ParamValues& MainWindow::values() const {
  return doc_ ? doc_->values() : kEmpty;
}

std::shared_ptr<const Dataset> MainWindow::dataset() const {
  return runner_->dataset();
}

void MainWindow::requestRun() {
  if (!scenario_ || !panel_) return;
  if (applied_latest_) since_request_.start();
  applied_latest_ = false;
  // An error shown before this request is cleared when the request succeeds.
  if (error_->isVisible()) error_->setProperty("fromRun", true);
  runner_->request(doc_->values());
}

void MainWindow::applyResult(std::shared_ptr<const RunResult> r, const ParamValues& v, double ms) {
  result_ = r;
  QElapsedTimer apply;
  apply.start();
  const std::size_t cursor_before = transport_->cursor();
  transport_->setTimes(r->t);
  {
    plot::DrawBatch batch;  // the view's reductions on both cores (draw_batch.h)
    view_->setDataset(runner_->dataset());
    view_->setResult(r, v);  // draws up to the view's cursor
    if (transport_->cursor() != cursor_before) view_->setCursor(transport_->cursor());
  }
  consistency_->setResult(r);  // drawn when its tab is shown
  if (qEnvironmentVariableIsSet("KFW_TIMING")) {
    qInfo("run %.1f ms, plots %.1f ms, since request %.1f ms", ms, apply.nsecsElapsed() / 1e6,
          since_request_.nsecsElapsed() / 1e6);
    for (const auto& p : plots_)
      qInfo("  %s replot %.1f ms", qPrintable(p.name), p.plot->replotTime());
  }
  if (!snapshots_.empty() && snapshots_.front().data != runner_->dataset()) {
    refreshSnapshots();
  } else {
    fillMetrics();
  }
  applied_latest_ = !runner_->busy();
  if (applied_latest_) last_latency_ms_ = static_cast<double>(since_request_.nsecsElapsed()) / 1e6;
  // The status bar: results and warnings (a screenshot stays the same run to run); the
  // timings in its tooltip.
  status_->setText(statusText());
  status_->setToolTip(QString("%1 steps · run %2 ms · request→plots %3 ms")
                          .arg(r->steps())
                          .arg(ms, 0, 'f', 1)
                          .arg(last_latency_ms_, 0, 'f', 1));
  status_->setStyleSheet(r->warnings.empty() ? QString() : QString("QLabel { color: #8a4b00; }"));
  if (applied_latest_) {
    // A later success clears the error banner (a run error, or one shown before the request).
    if (error_->isVisible() && error_->property("fromRun").toBool()) clearError();
    emit resultApplied();
  }
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

double MainWindow::lastRunMs() const {
  return runner_ ? runner_->lastCpuMs() : 0.0;
}

bool MainWindow::waitForRun(int timeout_ms) {
  // A nested event loop that sleeps until the run lands (no busy polling: the worker keeps a core).
  QDeadlineTimer deadline(timeout_ms);
  while (!applied_latest_ || runner_->busy() || (view_ && view_->busy())) {
    if (deadline.hasExpired()) return false;
    QEventLoop loop;
    connect(this, &MainWindow::resultApplied, &loop, &QEventLoop::quit);
    connect(runner_, &RunController::failed, &loop, &QEventLoop::quit);
    if (view_) connect(view_.get(), &ScenarioView::idle, &loop, &QEventLoop::quit);
    QTimer::singleShot(std::max<qint64>(1, std::min<qint64>(deadline.remainingTime(), 50)), &loop,
                       &QEventLoop::quit);
    loop.exec();
  }
  return true;
}

std::string MainWindow::primaryParameter() const {
  if (!scenario_) return {};
  const auto& specs = scenario_->params().specs();
  for (const auto& s : specs) {
    if (s.key == "Q") return s.key;
  }
  for (const auto& s : specs) {
    if (!is_sim_key(s.key) && (s.scale == Scale::kLog || s.scale == Scale::kLinear)) return s.key;
  }
  return specs.empty() ? std::string() : specs.front().key;
}

}  // namespace kfw
