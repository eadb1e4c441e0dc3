// The workbench window: preset picker, generated parameter panel, scenario plots, replay
// transport, CSV loading and export. Knows no scenario by name: everything comes from the
// engine's registry and the view registry. It lays out the widgets and wires the controllers
// that do the work: the document (values, undo, pins, sessions), the data, the runs, the
// replay, the export and the presentation; its public methods forward to them.
#pragma once

#include <QList>
#include <QMainWindow>
#include <QPointer>
#include <QString>
#include <QStringList>
#include <functional>
#include <memory>
#include <optional>

#include "core/expected.h"
#include "core/scenario.h"
#include "data_controller.h"
#include "document_controller.h"
#include "export_controller.h"
#include "plot_export.h"
#include "presentation_controller.h"
#include "replay_controller.h"
#include "run_controller.h"
#include "scenario_view.h"

class QAction;
class QMenu;
class QCustomPlot;
class QComboBox;
class QLabel;
class QScrollArea;
class QVBoxLayout;
class QPushButton;

namespace kfw {

class ConsistencyPanel;
class DataTab;
class ImportDialog;
class MetricsPanel;
class MonteCarloDialog;
class ParamPanel;
class SweepDialog;
class TransportBar;
class TuneDialog;
namespace plot {
class ZoomGroup;
}

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;
  // Whether the window reads and writes its remembered size (QSettings "window/geometry"); by
  // default not on the offscreen platform (tests, exports). Tests set it; nullopt: the default.
  static void setRemembersSize(std::optional<bool> on);

  // The controllers the window wires; a feature goes into the one that owns what it changes.
  DocumentController* documentController() const { return doc_; }
  DataController* dataController() const { return data_; }
  RunController* runController() const { return runs_; }
  ReplayController* replayController() const { return replay_; }
  ExportController* exportController() const { return export_; }
  PresentationController* presentationController() const { return present_; }

  // Loads a preset (path or name in presets/), optionally with another dataset and --set values.
  // On failure nothing changes and the message names the file/line/key.
  // `import`: how the file data in force is read (kfw-cli's import options).
  Status loadPreset(const QString& preset, const std::optional<QString>& data_file = {},
                    const QStringList& assignments = {}, const ImportArgs& import = {},
                    const QString& ask = {}) {
    return doc_->loadPreset(preset, data_file, assignments, import, ask);
  }
  // Loads a CSV for the current scenario. On failure the loaded dataset stays and the error shows.
  Status openDataset(const QString& path) { return data_->openDataset(path); }
  // Switches back to data simulated from the sim.* parameters.
  void useSimulatedData() { data_->useSimulatedData(); }
  // Sets a parameter as a user would (through its control); the run follows.
  void setParam(const std::string& key, double value);
  Status savePreset(const QString& path) const { return doc_->savePreset(path); }
  // Loads a CSV whose columns are named otherwise, with role -> column; remembered per header.
  Status openDatasetMapped(const QString& path, const ColumnMap& map) {
    return data_->openDatasetMapped(path, map);
  }
  Status openDatasetMapped(const QString& path, const Mapping& map) {
    return data_->openDatasetMapped(path, map);
  }
  // Undo / redo through the document (values, data, mapping, snapshot deletion).
  bool undo() { return doc_->undo(); }
  bool redo() { return doc_->redo(); }
  // The open document (preset, values, data, snapshots, history); null before a preset loads.
  const Document* document() const { return doc_->document(); }
  // Pins the live tuning as a named snapshot: ghost curves and a metrics column.
  void pinSnapshot(const QString& name) { doc_->pin(name); }
  void clearSnapshots() { doc_->clearPins(); }
  int snapshotCount() const { return doc_->pinCount(); }
  // Sessions: everything set up here, in one JSON file (atomic write).
  Status saveSession(const QString& path) const { return doc_->saveSession(path); }
  // Opens a CSV (data), preset or session by what the file is (.json: a session when its format
  // says so) or as `as`; on success it heads the recent files (main_window_files.cpp).
  enum class OpenAs { kData, kPreset, kSession };
  Status openAnyFile(const QString& path, std::optional<OpenAs> as = {});
  static OpenAs openAsFor(const QString& path);
  // The recent files, newest first (QSettings "recent/files", at most kRecentFiles).
  static QStringList recentFiles();
  static constexpr int kRecentFiles = 10;
  // Ctrl+S: the session last opened or saved, else asks where; saveSessionAs remembers the path.
  Status saveSessionHere();
  Status saveSessionAs(const QString& path);
  // kfw-cli run … and kfw --export … reproducing the preset, values, data and mapping
  // (document/command_line.h); copyCommandLine puts them on the clipboard.
  QString commandLine() const;
  void copyCommandLine();
  // File → Export filter as C… (main_window_c_export.cpp): the open preset's filter at the
  // window's values into `dir` (codegen/c_export.h; an empty prefix: the preset's file name).
  Status exportFilterAsC(const QString& dir, const QString& prefix, bool single, bool steady);
  void exportFilterAsCWithDialog();
  Status loadSession(const QString& path, const QString& ask = {}) {
    return doc_->loadSession(path, ask);
  }
  // The session's view state (opaque to the engine): a JSON object with the window geometry,
  // the splitters and one key per registered part. A part (the plots' zoom, the replay
  // position, ...) registers once: `save` gives its JSON value, `restore` takes it back.
  QString viewState() const { return doc_->viewState(); }
  void restoreViewState(const QString& state) { doc_->restoreViewState(state); }
  void addViewStatePart(const QString& key, std::function<QJsonValue()> save,
                        std::function<void(const QJsonValue&)> restore) {
    doc_->addViewStatePart(key, std::move(save), std::move(restore));
  }
  // When true, Open CSV… opens the import dialog (the GUI); tests and exports stay silent and use
  // the preset's or the remembered mapping. A cancelled dialog changes nothing and returns Ok.
  void setInteractive(bool on) { data_->setInteractive(on); }
  // Tests drive the import dialog through this instead of exec(): set roles, return true for OK
  // (refused while the dialog reports a problem). Set, it opens on every openDataset().
  void setImportHook(std::function<bool(ImportDialog&)> hook) {
    data_->setImportHook(std::move(hook));
  }
  // The Data menu: the import dialog on the current file (an undoable mapping change), forget
  // the mapping remembered for its header, write the converted data in kfw's CSV format.
  Status editMapping() { return data_->editMapping(); }
  Status forgetMapping() { return data_->forgetMapping(); }
  Status saveConvertedCsv(const QString& path) const { return data_->saveConvertedCsv(path); }
  // The Data tab: any column of the current dataset over time.
  QComboBox* dataColumnCombo() const;
  QCustomPlot* dataPlot() const;
  // Sets many values at once (a tuning result) and runs once.
  void applyValues(const ParamValues& values) { doc_->setValues(values, "apply values"); }
  // Opens the auto-tune / sweep dialogs on the current dataset and values (non-modal). Their
  // results go through the document's undo stack.
  TuneDialog* openTuneDialog();
  SweepDialog* openSweepDialog();
  MonteCarloDialog* openMonteCarloDialog();
  // Sets values as one named undo step (a tuning, its revert, a sweep point) and runs once.
  void applyValuesAs(const ParamValues& values, const QString& label) {
    doc_->setValues(values, label);
  }
  // Asks before throwing away unsaved changes or pinned snapshots (switching preset, opening a
  // session, quitting); true: go ahead. Tests answer through setConfirmHandler.
  bool confirmDiscard(const QString& action) { return doc_->confirmDiscard(action); }
  void setConfirmHandler(std::function<bool(const QString&)> handler) {
    doc_->setConfirmHandler(std::move(handler));
  }

  // Waits (processing events) until the latest request has run and its plots are drawn.
  bool waitForRun(int timeout_ms = 20000) { return runs_->waitSettled(timeout_ms); }
  // Every plot (or those named in `only`) in every format, all or nothing; files named
  // <preset>_<plot>.<format>.
  Expected<QStringList> exportAll(const QString& dir, const QStringList& formats,
                                  const ExportSpec& spec = {}, const QStringList& only = {}) {
    return export_->exportAll(dir, formats, spec, only);
  }

  ParamPanel* paramPanel() const { return panel_; }
  ScenarioView* view() const { return view_.get(); }
  const QList<PlotPanel>& plots() const { return plots_; }
  // What --export writes: the scenario's plots, then the consistency panel's per channel.
  QList<ExportItem> exportedPlots() const { return export_->exportedPlots(); }
  // The stable names of exportedPlots() (kfw --list-plots).
  QStringList plotNames() const { return export_->plotNames(); }
  // Look: the theme of the window and its plots; presentation mode (full screen, fonts × scale,
  // strong pens, the chosen plots only); screenshot mode (no live timings in the status bar, so
  // two screenshots are identical).
  void setTheme(Theme theme) { present_->setTheme(theme); }
  Theme theme() const { return present_->theme(); }
  void setPresentation(bool on) { present_->setPresentation(on); }
  bool presentation() const { return present_->presentation(); }
  void setPresentationScale(double scale) { present_->setScale(scale); }
  double presentationScale() const { return present_->scale(); }
  void setPresentedPlots(const QStringList& names) { present_->setPresentedPlots(names); }
  QStringList presentedPlots() const { return present_->presentedPlots(); }
  void setScreenshotMode(bool on) { present_->setScreenshotMode(on); }
  TransportBar* transport() const { return transport_; }
  // The user's zoom and the readout over the scenario's plots (widgets/plot_zoom.h).
  plot::ZoomGroup* zoom() const;
  ConsistencyPanel* consistency() const { return consistency_; }
  std::shared_ptr<const RunResult> result() const { return runs_->result(); }
  std::shared_ptr<const Dataset> dataset() const { return runs_->dataset(); }
  const ParamValues& values() const { return doc_->values(); }
  QString lastError() const { return last_error_; }
  const Preset& preset() const { return doc_->preset(); }
  std::shared_ptr<const Scenario> scenario() const { return doc_->scenario(); }
  // The parameter a user drags most: Q when there is one, else the first continuous filter one.
  std::string primaryParameter() const;
  // Request → plots replotted, for the last run, ms.
  double lastLatencyMs() const { return runs_->lastLatencyMs(); }
  // The last settled run's exit code (0 ran; 2 refused; 1 broke down), as kfw-cli's.
  int lastRunExitCode() const { return runs_->lastExitCode(); }
  // The metrics table (metrics_panel.h).
  MetricsPanel* metricsPanel() const { return metrics_; }
  // The metric shown first in the table (the last tuning's objective); "" for the default.
  void setPrimaryMetric(const std::string& key);
  // Back to the preset's values as one undo step; pinned snapshots stay.
  void resetToPreset() { doc_->resetToPreset(); }
  // The status bar's text: results and run warnings (timings are in its tooltip).
  QString statusText() const;
  // The preset's description as shown under the picker.
  QString presetDescription() const;
  // The README's usage section (Help → Usage) as Markdown; empty when no README is found.
  static QString usageText();
  // The README: in the source tree beside presets/, else installed beside the executable.
  static QString readmePath();
  // The About text: version and licences.
  static QString aboutText();
  // The time range every time plot shows (the replay's following window); x1 <= x0: no change.
  void applyTimeWindow(double t0, double t1) { replay_->applyTimeWindow(t0, t1); }

 signals:
  void resultApplied();
  void errorShown(const QString& message);

 protected:
  void closeEvent(QCloseEvent* event) override;
  // Re-fits the metrics table to the new height (fitMetricsPanel) once the layout has settled.
  void resizeEvent(QResizeEvent* event) override;
  // The first show brings the frame (decorations now known) inside the screen.
  void showEvent(QShowEvent* event) override;
  // A CSV, preset or session dropped on the window opens (openAnyFile).
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;

 private:
  QWidget* buildLeft();    // preset picker, data, tools; the parameters go in per preset
  QWidget* buildCenter();  // error banner, plots / consistency / data tabs, transport
  void buildMenus();
  void buildFileMenu();
  void rememberRecent(const QString& path);
  void fillRecentMenu();
  void buildToolsMenus();
  void wireControllers();
  void registerViewState();  // the session's view state: window, splitters, zoom, look, replay
  void fitToScreen();        // initial size from the screen (or the last size)
  void saveWindowSize() const;
  // Presenting, the left column is the parameters': the description hides, the metrics table
  // keeps the primary metric's row; leaving gives back the column as it was.
  void presentationChanged(bool on);
  void keepOnScreen();                   // the frame inside the screen's available geometry
  void placeOverPlots(QWidget* dialog);  // a tool dialog beside the left column, not over it
  void refreshPresetList();
  void presetChosen(int index);
  // Per document (main_window_scenario.cpp): its controls and plots, its runs drawn.
  void documentReplaced();
  void rebuildScenarioUi();
  void rebuildPlots();
  void applyResult(std::shared_ptr<const RunResult> r, const ParamValues& v, double ms);
  void runApplied(bool ok);
  void showError(const QString& message, bool from_run = false);
  void clearError();
  void updateDescription();
  void updateDataLabel();
  void updateUndoActions();
  void showPins();
  void fillMetrics();
  // Gives the metrics table (leftSplit) the height that shows the primary metric's group without
  // scrolling, from the parameters above it, unless the user has moved that splitter.
  void fitMetricsPanel();

  RunController* runs_ = nullptr;
  DocumentController* doc_ = nullptr;
  DataController* data_ = nullptr;
  ReplayController* replay_ = nullptr;
  ExportController* export_ = nullptr;
  PresentationController* present_ = nullptr;

  std::shared_ptr<ScenarioView> view_;
  QList<PlotPanel> plots_;
  ParamPanel* panel_ = nullptr;
  QWidget* controls_ = nullptr;
  TransportBar* transport_ = nullptr;
  QComboBox* presets_ = nullptr;
  QLabel* data_label_ = nullptr;
  QPushButton* sim_button_ = nullptr;
  QPushButton* data_fix_ = nullptr;  // "Use the file: set mode=replay" when the mode ignores it
  QVBoxLayout* left_ = nullptr;
  QScrollArea* plot_area_ = nullptr;
  ConsistencyPanel* consistency_ = nullptr;
  DataTab* data_tab_ = nullptr;
  QWidget* plot_host_ = nullptr;
  QPointer<plot::ZoomGroup> zoom_;  // a child of plot_host_
  MetricsPanel* metrics_ = nullptr;
  bool metrics_split_by_user_ = false;
  std::string primary_metric_;  // the last tuning's objective ("" until one)
  QLabel* description_ = nullptr;
  QLabel* error_ = nullptr;
  QLabel* status_ = nullptr;
  QString last_error_;
  QAction* undo_action_ = nullptr;
  QAction* redo_action_ = nullptr;
  bool shown_once_ = false;
  QMenu* recent_menu_ = nullptr;
  QString session_path_;  // Ctrl+S saves here
  QSize fitted_size_;     // the size fitToScreen() chose
  QList<int> left_sizes_before_present_;
};

}  // namespace kfw
