// MainWindow: the layout, the menus and the wiring of the controllers. What happens per
// document (controls, plots, a run drawn) is in main_window_scenario.cpp.
#include "main_window.h"

#include <qcustomplot.h>

#include <QCloseEvent>
#include <QComboBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QGuiApplication>
#include <QJsonObject>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>

#include "consistency_panel.h"
#include "data_tab.h"
#include "help_menu.h"
#include "metrics_panel.h"
#include "monte_carlo_dialog.h"
#include "param_panel.h"
#include "plot_zoom.h"
#include "sweep_dialog.h"
#include "transport_bar.h"
#include "tune_dialog.h"
#include "window_report.h"

namespace kfw {

using window::q;
using window::report;

namespace {

QPushButton* button(const QString& text, const char* name, const QString& tip = {}) {
  auto* b = new QPushButton(text);
  b->setObjectName(name);
  if (!tip.isEmpty()) b->setToolTip(tip);
  return b;
}

// The left column: as wide as its widest row needs (units, spin boxes, Reset whole at any font
// size), scrolling only down. An explicit minimum width cut the rows at 1366 × 768 and larger
// text, with a scroll bar sideways.
class ColumnScroll : public QScrollArea {
 public:
  QSize minimumSizeHint() const override {
    QSize s = QScrollArea::minimumSizeHint();
    if (widget()) {
      const int need = widget()->minimumSizeHint().width() +
                       verticalScrollBar()->sizeHint().width() + 2 * frameWidth();
      s.setWidth(std::max(kMinWidth, need));
    }
    return s;
  }
  static constexpr int kMinWidth = 300;
};

std::optional<bool>& remembersOverride() {
  static std::optional<bool> on;
  return on;
}

// Offscreen runs (tests, exports, screenshots) neither read nor write the remembered size.
bool remembersSize() {
  if (remembersOverride()) return *remembersOverride();
  return QGuiApplication::platformName() != "offscreen";
}
}  // namespace

void MainWindow::setRemembersSize(std::optional<bool> on) {
  remembersOverride() = on;
}

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setWindowTitle("kfw — Kalman filter tuning workbench");
  runs_ = new RunController(this);
  doc_ = new DocumentController(runs_, this);
  data_ = new DataController(doc_, runs_, this);  // its adopt step reads the data first
  auto* split = new QSplitter(Qt::Horizontal);
  split->setObjectName("mainSplit");
  split->addWidget(buildLeft());
  split->addWidget(buildCenter());
  split->setStretchFactor(1, 1);
  split->setSizes({380, 1220});
  setCentralWidget(split);
  status_ = new QLabel;
  status_->setObjectName("status");
  statusBar()->addWidget(status_, 1);
  replay_ = new ReplayController(transport_, consistency_, this);
  export_ = new ExportController(runs_, consistency_, this);
  present_ = new PresentationController(this, status_);
  buildMenus();
  wireControllers();
  refreshPresetList();
  fitToScreen();
}

MainWindow::~MainWindow() = default;

QWidget* MainWindow::buildLeft() {
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
  connect(presets_, &QComboBox::activated, this, &MainWindow::presetChosen);
  data_label_ = new QLabel;
  data_label_->setObjectName("dataLabel");
  data_label_->setWordWrap(true);
  left_->addWidget(data_label_);
  auto* data_row = new QHBoxLayout;
  auto* open_csv = button("Open CSV…", "openCsv");
  sim_button_ = button("Use simulated data", "useSimulated");
  data_row->addWidget(open_csv);
  data_row->addWidget(sim_button_);
  left_->addLayout(data_row);
  connect(open_csv, &QPushButton::clicked, this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open dataset", QString(), "CSV (*.csv);;All files (*)");
    if (!f.isEmpty()) report(this, "Open CSV", openDataset(f));
  });
  connect(sim_button_, &QPushButton::clicked, data_, &DataController::useSimulatedData);
  auto* tool_row = new QHBoxLayout;
  auto* tune = button("Tune…", "tuneButton",
                      "Search Q, R, … for the best RMSE / likelihood / NIS consistency");
  auto* sweep = button("Sweep…", "sweepButton", "Plot any metric over one or two parameters");
  auto* pin = button("Pin", "pinButton",
                     "Keep the current tuning, under a name, as a ghost and a metrics column");
  auto* reset = button("Reset", "resetButton",
                       "Back to the preset's values (one undo step; pinned snapshots stay)");
  for (QPushButton* b : {tune, sweep, pin, reset})
    tool_row->addWidget(b);
  connect(reset, &QPushButton::clicked, doc_, &DocumentController::resetToPreset);
  connect(pin, &QPushButton::clicked, this, [this] { doc_->askPin("Name of this tuning:", true); });
  left_->addLayout(tool_row);
  connect(tune, &QPushButton::clicked, this, [this] { openTuneDialog(); });
  connect(sweep, &QPushButton::clicked, this, [this] { openSweepDialog(); });
  // The panel and scenario controls are inserted here by rebuildScenarioUi().
  left_->addStretch(0);
  metrics_ = new MetricsPanel;

  auto* left_scroll = new ColumnScroll;
  left_scroll->setObjectName("leftScroll");
  left_scroll->setWidget(left_host);
  left_scroll->setWidgetResizable(true);
  left_scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  auto* left_split = new QSplitter(Qt::Vertical);
  left_split->setObjectName("leftSplit");
  left_split->addWidget(left_scroll);
  left_split->addWidget(metrics_);
  left_split->setStretchFactor(0, 3);
  left_split->setStretchFactor(1, 2);
  return left_split;
}

QWidget* MainWindow::buildCenter() {
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
  data_tab_ = new DataTab;
  tabs->addTab(data_tab_, "Data");
  cl->addWidget(tabs, 1);
  transport_ = new TransportBar;
  transport_->setObjectName("transport");
  cl->addWidget(transport_);
  return center;
}

void MainWindow::buildMenus() {
  buildFileMenu();  // main_window_files.cpp
  QMenu* edit = menuBar()->addMenu("&Edit");
  undo_action_ = edit->addAction("&Undo", QKeySequence::Undo, this, [this] { undo(); });
  undo_action_->setObjectName("undoAction");
  redo_action_ = edit->addAction("&Redo", QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), this,
                                 [this] { redo(); });
  redo_action_->setObjectName("redoAction");
  edit->addSeparator();
  edit->addAction("Reset to &preset values", QKeySequence(Qt::CTRL | Qt::Key_R), doc_,
                  &DocumentController::resetToPreset);
  QAction* copy =
      edit->addAction("&Copy command line", QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_C), this,
                      &MainWindow::copyCommandLine);
  copy->setObjectName("copyCommandLine");
  copy->setToolTip(
      "kfw-cli run … and kfw --export … with this preset, the changed values, the "
      "data and its mapping; leaves out pinned snapshots, zoom, the replay cursor "
      "and presentation");
  edit->setToolTipsVisible(true);
  updateUndoActions();
  buildToolsMenus();
  present_->buildMenu(menuBar());
  help::addMenu(this);  // last: Help is the right-most menu
}

void MainWindow::buildToolsMenus() {
  QMenu* tools = menuBar()->addMenu("&Tools");
  tools->addAction("Auto-&tune…", QKeySequence(Qt::CTRL | Qt::Key_T), this,
                   [this] { openTuneDialog(); });
  tools->addAction("&Sweep a metric…", QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_T), this,
                   [this] { openSweepDialog(); });
  tools->addAction("&Monte Carlo over seeds…", QKeySequence(Qt::CTRL | Qt::Key_M), this,
                   [this] { openMonteCarloDialog(); });
  tools->addAction("&Pin snapshot…", QKeySequence(Qt::CTRL | Qt::Key_P), this,
                   [this] { doc_->askPin("Name:", false); });
  tools->addAction("&Clear snapshots", doc_, &DocumentController::clearPins);
  // The replay keys (Space, ←, →, Home, End) work with any focus but text entry
  // (replay_controller.cpp); the menu names them.
  QMenu* replay = menuBar()->addMenu("&Replay");
  replay->addAction("&Play / pause\tSpace", this, [this] { transport_->togglePlay(); });
  replay->addAction("Step &back\t←", this, [this] { transport_->stepBy(-1); });
  replay->addAction("Step &forward\t→", this, [this] { transport_->stepBy(1); });
  replay->addAction("To the &start\tHome", this, [this] { transport_->seek(0); });
  replay->addAction("To the &end\tEnd", this,
                    [this] { transport_->seek(static_cast<std::size_t>(-1)); });
  replay->addAction("Show &all", this, [this] { transport_->setShowAll(true); });
  QMenu* data_menu = menuBar()->addMenu("&Data");
  data_menu->addAction("&Mapping…", this, [this] { report(this, "Mapping", editMapping()); });
  data_menu->addAction("&Forget remembered mapping", this,
                       [this] { report(this, "Forget mapping", forgetMapping()); });
  data_menu->addAction("&Save as kfw CSV…", this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save as kfw CSV", QString(), "CSV (*.csv)");
    if (!f.isEmpty()) report(this, "Save as kfw CSV", saveConvertedCsv(f));
  });
}

void MainWindow::wireControllers() {
  // A new document's plots come from the view registry (after its data are read).
  doc_->addAdoptStep([this](const Document& d) -> Expected<DocumentController::Commit> {
    std::shared_ptr<ScenarioView> view = views().make(d.scenario().name());
    if (!view) return Error{"no plots registered for scenario '" + d.scenario().name() + "'"};
    return DocumentController::Commit([this, view] { view_ = view; });
  });
  connect(doc_, &DocumentController::documentReplaced, this, &MainWindow::documentReplaced);
  connect(doc_, &DocumentController::changed, this, [this] {
    if (panel_) panel_->setValues(values());
  });
  connect(doc_, &DocumentController::historyChanged, this, &MainWindow::updateUndoActions);
  connect(doc_, &DocumentController::pinsChanged, this, &MainWindow::showPins);
  connect(doc_, &DocumentController::problem, this, [this](const QString& m) { showError(m); });
  connect(data_, &DataController::dataChanged, this, &MainWindow::updateDataLabel);
  connect(data_, &DataController::fileOpened, this, &MainWindow::clearError);
  connect(data_, &DataController::problem, this, [this](const QString& m) { showError(m); });
  connect(data_, &DataController::status, status_, &QLabel::setText);
  connect(export_, &ExportController::status, status_, &QLabel::setText);
  connect(this, &MainWindow::errorShown, export_, &ExportController::noteProblem);
  connect(runs_, &RunController::finished, this, &MainWindow::applyResult);
  connect(runs_, &RunController::failed, this, [this](const QString& m) { showError(m, true); });
  connect(runs_, &RunController::applied, this, &MainWindow::runApplied);
  connect(runs_, &RunController::requested, this, [this] {
    // An error shown before this request is cleared when the request succeeds.
    if (error_->isVisible()) error_->setProperty("fromRun", true);
  });
  runs_->setDrawing([this] { return view_ && view_->busy(); });
  connect(runs_, &RunController::problem, this, [this](const QString& m) { showError(m); });
  connect(runs_, &RunController::valuesChosen, doc_, &DocumentController::setValues);
  connect(runs_, &RunController::tuningSetChosen, doc_, &DocumentController::setTuningSet);
  connect(runs_, &RunController::objectiveChosen, this,
          [this](const QString& key) { primary_metric_ = key.toStdString(); });
  present_->setPlotSources([this] { return plots_; },
                           [this] {
                             QList<QCustomPlot*> others;
                             for (const PlotPanel& p : consistency_->plots())
                               others << p.plot;
                             others << data_tab_->plot();
                             return others;
                           });
  // After each run: the data tab and label, the look of new curves, the readout at the cursor.
  connect(this, &MainWindow::resultApplied, this, [this] {
    data_tab_->setDataset(dataset());
    updateDataLabel();
  });
  connect(this, &MainWindow::resultApplied, present_, &PresentationController::restyle);
  connect(present_, &PresentationController::presentationChanged, this,
          &MainWindow::presentationChanged);
  connect(this, &MainWindow::resultApplied, replay_, &ReplayController::followCursor);
  registerViewState();
}

void MainWindow::registerViewState() {
  // The window, then each part, restored in this order.
  addViewStatePart(
      "geometry", [this] { return QJsonValue(QString::fromLatin1(saveGeometry().toBase64())); },
      [this](const QJsonValue& v) {
        restoreGeometry(QByteArray::fromBase64(v.toString().toLatin1()));
      });
  addViewStatePart(
      "splitters",
      [this] {
        QJsonObject splits;
        for (auto* sp : findChildren<QSplitter*>()) {
          if (!sp->objectName().isEmpty())
            splits[sp->objectName()] = QString::fromLatin1(sp->saveState().toBase64());
        }
        return QJsonValue(splits);
      },
      [this](const QJsonValue& v) {
        const QJsonObject splits = v.toObject();
        for (auto it = splits.begin(); it != splits.end(); ++it) {
          if (auto* sp = findChild<QSplitter*>(it.key()))
            sp->restoreState(QByteArray::fromBase64(it.value().toString().toLatin1()));
        }
      });
  addViewStatePart(
      "zoom", [this] { return zoom_ ? zoom_->save() : QJsonValue(); },
      [this](const QJsonValue& v) {
        if (zoom_) zoom_->restore(v);
      });
  addViewStatePart(
      "presentation", [this] { return present_->saveState(); },
      [this](const QJsonValue& v) { present_->restoreState(v); });
  addViewStatePart(
      "replay", [this] { return replay_->saveState(); },
      [this](const QJsonValue& v) { replay_->restoreState(v); });
}

void MainWindow::presetChosen(int index) {
  const QString path = presets_->itemData(index).toString();
  // The preset already open: back to its values (pinned snapshots stay, one undo step).
  if (document() && !preset().path.empty() &&
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

void MainWindow::fitToScreen() {
  if (remembersSize()) {
    const QByteArray g = QSettings("kfw", "kfw").value("window/geometry").toByteArray();
    if (!g.isEmpty() && restoreGeometry(g)) {
      keepOnScreen();
      fitted_size_ = size();
      return;
    }
  }
  // 90 % of the available screen, at most 1600×1000.
  const QScreen* s = screen() ? screen() : QGuiApplication::primaryScreen();
  const QRect avail = s ? s->availableGeometry() : QRect(0, 0, 1366, 768);
  const QSize size(std::min(1600, avail.width() * 9 / 10), std::min(1000, avail.height() * 9 / 10));
  resize(size);
  move(avail.center() - QPoint(size.width() / 2, size.height() / 2));
  keepOnScreen();
  fitted_size_ = this->size();
}

void MainWindow::keepOnScreen() {
  // A size remembered from a larger screen (or a layout that grew) must not run off this one:
  // the frame, decorations included, inside the available geometry.
  const QScreen* s = screen() ? screen() : QGuiApplication::primaryScreen();
  if (!s || isFullScreen() || isMaximized()) return;
  const QRect avail = s->availableGeometry();
  const QRect frame = frameGeometry();
  const QSize decor = frame.size() - size();
  const QSize most(std::max(minimumWidth(), avail.width() - decor.width()),
                   std::max(minimumHeight(), avail.height() - decor.height()));
  if (width() > most.width() || height() > most.height()) resize(size().boundedTo(most));
  QRect f = frameGeometry();
  f.moveLeft(
      std::clamp(f.left(), avail.left(), std::max(avail.left(), avail.right() - f.width() + 1)));
  f.moveTop(
      std::clamp(f.top(), avail.top(), std::max(avail.top(), avail.bottom() - f.height() + 1)));
  move(f.topLeft());
}

void MainWindow::saveWindowSize() const {
  if (remembersSize()) QSettings("kfw", "kfw").setValue("window/geometry", saveGeometry());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (confirmDiscard("Quit")) {
    saveWindowSize();
    event->accept();
  } else {
    event->ignore();
  }
}

void MainWindow::showEvent(QShowEvent* event) {
  QMainWindow::showEvent(event);
  // Only now are the decorations known (the frame margins): the first show brings the frame in,
  // unless a caller sized the window since (a test, --screenshot --size).
  if (!event->spontaneous() && !shown_once_ && size() == fitted_size_) {
    shown_once_ = true;
    QTimer::singleShot(0, this, [this] { keepOnScreen(); });
  }
}

void MainWindow::resizeEvent(QResizeEvent* event) {
  QMainWindow::resizeEvent(event);
  QTimer::singleShot(0, this, [this] { fitMetricsPanel(); });
}

TuneDialog* MainWindow::openTuneDialog() {
  if (!document() || !waitForRun()) return nullptr;
  const QString name =
      document()->data() ? QFileInfo(q(document()->data()->path)).fileName() : QString("simulated");
  TuneDialog* d = runs_->openTune(preset(), values(), name, document()->tuning_set(), this);
  present_->adopt(d);
  placeOverPlots(d);
  return d;
}

void MainWindow::placeOverPlots(QWidget* dialog) {
  // Over the plots, not the parameters and metrics a user reads beside the dialog's result.
  if (!dialog || !plot_area_->isVisible()) return;
  const QRect area(plot_area_->mapToGlobal(QPoint(0, 0)), plot_area_->size());
  const QSize s = dialog->size().boundedTo(area.size()).expandedTo(dialog->minimumSizeHint());
  dialog->resize(s);
  dialog->move(area.left() + std::max(0, (area.width() - s.width()) / 2),
               area.top() + std::max(0, (area.height() - s.height()) / 2));
}

MonteCarloDialog* MainWindow::openMonteCarloDialog() {
  if (!document()) return nullptr;
  MonteCarloDialog* d = runs_->openMonteCarlo(values(), this);
  present_->adopt(d);
  placeOverPlots(d);
  return d;
}

SweepDialog* MainWindow::openSweepDialog() {
  if (!document() || !waitForRun()) return nullptr;
  SweepDialog* d = runs_->openSweep(values(), this);
  present_->adopt(d);
  placeOverPlots(d);
  return d;
}

QString MainWindow::usageText() {
  return help::usageText();
}

QString MainWindow::readmePath() {
  return help::readmePath();
}

QString MainWindow::aboutText() {
  return help::aboutText();
}

}  // namespace kfw
