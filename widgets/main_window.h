// The workbench window: preset picker, generated parameter panel, scenario plots, replay
// transport, CSV loading and export. Knows no scenario by name: everything comes from the
// engine's registry and the view registry.
#pragma once

#include <QElapsedTimer>
#include <QJsonValue>
#include <QList>
#include <QMainWindow>
#include <QPointer>
#include <QString>
#include <QStringList>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "core/expected.h"
#include "core/scenario.h"
#include "document/document.h"
#include "document/preset.h"
#include "document/session.h"
#include "plot_export.h"
#include "scenario_view.h"

class QAction;
class QCustomPlot;
class QTabWidget;
class QComboBox;
class QLabel;
class QScrollArea;
class QTableWidget;
class QVBoxLayout;
class QGridLayout;
class QPushButton;
class QKeyEvent;

namespace kfw {

class ConsistencyPanel;
class ImportDialog;
class MetricsPanel;
class ParamPanel;
class RunController;
namespace plot {
class ZoomGroup;
}
class TransportBar;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  // Loads a preset (path or name in presets/), optionally with another dataset and --set values.
  // On failure nothing changes and the message names the file/line/key.
  Status loadPreset(const QString& preset, const std::optional<QString>& data_file = {},
                    const QStringList& assignments = {});
  // Loads a CSV for the current scenario. On failure the loaded dataset stays and the error shows.
  Status openDataset(const QString& path);
  // Switches back to data simulated from the sim.* parameters.
  void useSimulatedData();
  // Sets a parameter as a user would (through its control); the run follows.
  void setParam(const std::string& key, double value);
  Status savePreset(const QString& path) const;
  // Loads a CSV whose columns are named otherwise, with role -> column; remembered per header.
  Status openDatasetMapped(const QString& path, const ColumnMap& map);
  Status openDatasetMapped(const QString& path, const Mapping& map);
  // Undo / redo through the document (values, data, mapping, snapshot deletion).
  bool undo();
  bool redo();
  // The open document (preset, values, data, snapshots, history); null before a preset loads.
  const Document* document() const { return doc_.get(); }
  // Pins the live tuning as a named snapshot: ghost curves and a metrics column.
  void pinSnapshot(const QString& name);
  void clearSnapshots();
  int snapshotCount() const { return static_cast<int>(snapshots_.size()); }
  // Sessions: everything set up here, in one JSON file (atomic write).
  Status saveSession(const QString& path) const;
  Status loadSession(const QString& path);
  // The session's view state (opaque to the engine): a JSON object with the window geometry,
  // the splitters and one key per registered part. A part (the plots' zoom, the replay
  // position, ...) registers once: `save` gives its JSON value, `restore` takes it back.
  QString viewState() const;
  void restoreViewState(const QString& state);
  void addViewStatePart(const QString& key, std::function<QJsonValue()> save,
                        std::function<void(const QJsonValue&)> restore);
  // When true, Open CSV… opens the import dialog (the GUI); tests and exports stay silent and use
  // the preset's or the remembered mapping. A cancelled dialog changes nothing and returns Ok.
  void setInteractive(bool on) { interactive_ = on; }
  // Tests drive the import dialog through this instead of exec(): set roles, return true for OK
  // (refused while the dialog reports a problem). Set, it opens on every openDataset().
  void setImportHook(std::function<bool(ImportDialog&)> hook);
  // The Data menu: the import dialog on the current file (an undoable mapping change), forget
  // the mapping remembered for its header, write the converted data in kfw's CSV format.
  Status editMapping();
  Status forgetMapping();
  Status saveConvertedCsv(const QString& path) const;
  // The Data tab: any column of the current dataset over time.
  QComboBox* dataColumnCombo() const { return data_column_; }
  QCustomPlot* dataPlot() const { return data_plot_; }
  // Sets many values at once (a tuning result) and runs once.
  void applyValues(const ParamValues& values);
  // Opens the auto-tune / sweep dialogs on the current dataset and values (non-modal);
  // main_window_tune.cpp. Their results go through the document's undo stack.
  class TuneDialog* openTuneDialog();
  class SweepDialog* openSweepDialog();
  // Sets values as one named undo step (a tuning, its revert, a sweep point) and runs once.
  void applyValuesAs(const ParamValues& values, const QString& label);
  // Asks before throwing away unsaved changes or pinned snapshots (switching preset, opening a
  // session, quitting); true: go ahead. Tests answer through setConfirmHandler.
  bool confirmDiscard(const QString& action);
  void setConfirmHandler(std::function<bool(const QString&)> handler) {
    confirm_ = std::move(handler);
  }

  // Waits (processing events) until the latest request has run and its plots are drawn.
  bool waitForRun(int timeout_ms = 20000);
  // Export (main_window_export.cpp): every plot (or those named in `only`) in every format, all or
  // nothing; files named <preset>_<plot>.<format>.
  Expected<QStringList> exportAll(const QString& dir, const QStringList& formats,
                                  const ExportSpec& spec = {}, const QStringList& only = {});

  ParamPanel* paramPanel() const { return panel_; }
  ScenarioView* view() const { return view_.get(); }
  const QList<PlotPanel>& plots() const { return plots_; }
  // What --export writes: the scenario's plots, then the consistency panel's per channel.
  QList<ExportItem> exportedPlots() const;
  // The stable names of exportedPlots() (kfw --list-plots).
  QStringList plotNames() const;
  // Look (main_window_present.cpp): the theme of the window and its plots; presentation mode
  // (full screen, fonts × scale, strong pens, the chosen plots only); screenshot mode (no live
  // timings in the status bar, so two screenshots are identical).
  void setTheme(Theme theme);
  Theme theme() const { return theme_; }
  void setPresentation(bool on);
  bool presentation() const;
  void setPresentationScale(double scale);
  double presentationScale() const;
  void setPresentedPlots(const QStringList& names);
  QStringList presentedPlots() const;
  void setScreenshotMode(bool on);
  TransportBar* transport() const { return transport_; }
  // The user's zoom and the readout over the scenario's plots (widgets/plot_zoom.h).
  plot::ZoomGroup* zoom() const;
  ConsistencyPanel* consistency() const { return consistency_; }
  std::shared_ptr<const RunResult> result() const { return result_; }
  std::shared_ptr<const Dataset> dataset() const;
  const ParamValues& values() const;
  QString lastError() const { return last_error_; }
  const Preset& preset() const;
  std::shared_ptr<const Scenario> scenario() const { return scenario_; }
  // The parameter a user drags most: Q when there is one, else the first continuous filter one.
  std::string primaryParameter() const;
  // Request → plots replotted, for the last run, ms.
  double lastLatencyMs() const { return last_latency_ms_; }
  // The worker's CPU time in the last finished run (the latency benchmark adds it up).
  double lastRunMs() const;
  // The metrics table (metrics_panel.h).
  MetricsPanel* metricsPanel() const { return metrics_; }
  // The metric shown first in the table (the last tuning's objective); "" for the default.
  void setPrimaryMetric(const std::string& key);
  // Back to the preset's values as one undo step; pinned snapshots stay.
  void resetToPreset();
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
  void applyTimeWindow(double t0, double t1);

 signals:
  void resultApplied();
  void errorShown(const QString& message);

 protected:
  void closeEvent(QCloseEvent* event) override;
  // Re-fits the metrics table to the new height (fitMetricsPanel) once the layout has settled.
  void resizeEvent(QResizeEvent* event) override;

 private:
  void buildMenus();
  void buildHelpMenu();  // main_window_help.cpp, with the window's size and the description
  void fitToScreen();    // initial size from the screen (or the last size)
  void saveWindowSize() const;
  void updateDescription();
  void setupReplay();  // main_window_replay.cpp: keys with any focus, following window
  bool replayKey(QObject* target, QKeyEvent* event);
  friend class ReplayKeys;
  void buildViewMenu();  // main_window_present.cpp
  void restyleLook();    // new plots or curves take the theme and presentation look
  void rebuildScenarioUi();
  void requestRun();
  void applyResult(std::shared_ptr<const RunResult> r, const ParamValues& v, double ms);
  void showError(const QString& message, bool from_run = false);
  void clearError();
  void refreshPresetList();
  void updateDataLabel();  // main_window_data.cpp, with the Data menu and tab
  void buildDataMenu();
  void buildDataTab(QTabWidget* tabs);
  void refreshDataTab();
  void plotDataColumn();

  struct Pinned {
    Snapshot snap;
    std::shared_ptr<const RunResult> result;
    std::shared_ptr<const Dataset> data;
  };
  void refreshSnapshots();
  void fillMetrics();
  // Gives the metrics table (leftSplit) the height that shows the primary metric's group without
  // scrolling, from the parameters above it, unless the user has moved that splitter.
  void fitMetricsPanel();
  bool metrics_split_by_user_ = false;
  Status adoptDocument(Document doc);
  // Reads `path` for the scenario; with no mapping, tries the file as it is, then a mapping
  // remembered for its header, then (interactive) the mapping dialog. `used` gets the mapping.
  Expected<Dataset> readMapped(const QString& path, const Mapping* map, Mapping& used);
  Status openFile(const QString& path, const Mapping* map);
  // Makes the window show what the document holds (after undo/redo): values, data, snapshots.
  void syncFromDocument();
  void updateUndoActions();

  std::shared_ptr<const Scenario> scenario_;
  std::unique_ptr<Document> doc_;
  std::vector<Pinned> snapshots_;       // the document's snapshots with their runs
  std::optional<DataRef> loaded_data_;  // what file_data_ was read from
  std::string last_edit_key_;           // slider drags join one undo step
  QElapsedTimer last_edit_;
  QAction* undo_action_ = nullptr;
  QAction* redo_action_ = nullptr;
  bool interactive_ = false;
  std::function<bool(ImportDialog&)> import_hook_;
  QComboBox* data_column_ = nullptr;
  QCustomPlot* data_plot_ = nullptr;
  QPushButton* data_fix_ = nullptr;  // "Use the file: set mode=replay" when the mode ignores it
  std::shared_ptr<const Dataset> data_tab_source_;
  std::unique_ptr<ScenarioView> view_;
  std::shared_ptr<const Dataset> file_data_;
  std::shared_ptr<const RunResult> result_;
  QList<PlotPanel> plots_;
  RunController* runner_ = nullptr;
  ParamPanel* panel_ = nullptr;
  QWidget* controls_ = nullptr;
  TransportBar* transport_ = nullptr;
  QComboBox* presets_ = nullptr;
  QLabel* data_label_ = nullptr;
  QPushButton* sim_button_ = nullptr;
  QVBoxLayout* left_ = nullptr;
  QScrollArea* plot_area_ = nullptr;
  ConsistencyPanel* consistency_ = nullptr;
  QWidget* plot_host_ = nullptr;
  QPointer<plot::ZoomGroup> zoom_;  // a child of plot_host_
  MetricsPanel* metrics_ = nullptr;
  std::string primary_metric_;  // the last tuning's objective ("" until one)
  QLabel* description_ = nullptr;
  QLabel* error_ = nullptr;
  QLabel* status_ = nullptr;
  QString last_error_;
  QElapsedTimer since_request_;
  double last_latency_ms_ = 0.0;
  bool applied_latest_ = true;
  std::function<bool(const QString&)> confirm_;  // empty: a message box asks
  struct ViewPart {
    QString key;
    std::function<QJsonValue()> save;
    std::function<void(const QJsonValue&)> restore;
  };
  std::vector<ViewPart> view_parts_;
  class Presentation* present_ = nullptr;  // main_window_present.cpp
  Theme theme_ = Theme::kLight;
  bool screenshot_mode_ = false;
};

}  // namespace kfw
