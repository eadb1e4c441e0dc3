// The open document in the window: the engine's Document (preset, values, data, tuning set,
// snapshots, undo history) with what the GUI adds to it — slider drags joined into one undo
// step, the pinned snapshots' runs (ghosts and metrics columns), sessions with their view state,
// and the question before unsaved work is thrown away. Every change asks the runs for a new run.
#pragma once

#include <QElapsedTimer>
#include <QJsonValue>
#include <QList>
#include <QObject>
#include <QPair>
#include <QString>
#include <QStringList>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "core/expected.h"
#include "core/scenario.h"
#include "document/document.h"

class QWidget;

namespace kfw {

class RunController;

class DocumentController : public QObject {
  Q_OBJECT
 public:
  // `window`: the parent of the controller and of its message boxes (may be null in tests).
  explicit DocumentController(RunController* runs, QWidget* window = nullptr);
  ~DocumentController() override;

  // What a new document needs before it replaces the open one (its data read, its plots made):
  // a step reads it and returns how to put it in place. Steps run in the order added; the first
  // that fails leaves everything as it was.
  using Commit = std::function<void()>;
  using AdoptStep = std::function<Expected<Commit>(const Document&)>;
  void addAdoptStep(AdoptStep step) { steps_.push_back(std::move(step)); }

  // Opens a preset (path or name in presets/), optionally with another dataset and --set values.
  // `import`: kfw-cli's import options over the preset's mapping (refused when it simulates).
  // `ask` (a menu action's name): once the file has loaded, confirmDiscard(ask) decides whether
  // it replaces the open document (a file that does not load is refused without a question).
  Status loadPreset(const QString& preset, const std::optional<QString>& data_file = {},
                    const QStringList& assignments = {}, const ImportArgs& import = {},
                    const QString& ask = {});
  // Makes `doc` the open document (adopt steps, then documentReplaced and a run).
  Status adopt(Document doc);
  // Null before a preset loads.
  const Document* document() const { return doc_.get(); }
  const Preset& preset() const;
  const ParamValues& values() const;
  std::shared_ptr<const Scenario> scenario() const;

  // A value from a control: changes of one key in quick succession (a slider drag) are one step.
  void setValue(const std::string& key, double value);
  // Many values as one named undo step (a tuning, its revert, a sweep point) and one run.
  void setValues(const ParamValues& values, const QString& label);
  // The document's data (none: simulated) and the mapping of its file; each one undo step.
  void setData(std::optional<DataRef> data);
  Status setMapping(const Mapping& mapping);
  // The tuning dialog's extra logs, read with the preset's mapping.
  void setTuningSet(const QStringList& paths);
  bool undo();
  bool redo();
  // Back to the preset's values as one undo step; pinned snapshots stay.
  void resetToPreset();
  // The undo / redo menu texts ("&Undo set R"), and whether each is possible.
  QString undoText() const;
  QString redoText() const;
  // Asks for a run of the document's values (nothing before a preset loads).
  void requestRun();

  // Pinned snapshots with their runs on the current dataset (null until run).
  struct Pin {
    Snapshot snap;
    std::shared_ptr<const RunResult> result;
    std::shared_ptr<const Dataset> data;
  };
  // Pins the live tuning (the last run) under a name: a ghost and a metrics column.
  void pin(const QString& name);
  // Asks for the name first (a dialog offering "snapshot N"); cancelled or empty: nothing.
  void askPin(const QString& prompt, bool trimmed);
  void clearPins();
  const std::vector<Pin>& pins() const { return pins_; }
  int pinCount() const { return static_cast<int>(pins_.size()); }
  // True when the pins were run on another dataset than the last run's.
  bool pinsStale() const;
  // Re-runs stale pins on the last run's dataset (synchronously: a few ms each); pinsChanged.
  void refreshPins();
  // The pins' runs by name: every pin (metrics columns) or those with a run (ghosts).
  QList<QPair<QString, std::shared_ptr<const RunResult>>> pinnedRuns(bool with_unrun) const;

  // Sessions: the document and the view state, in one JSON file (atomic write). Loading adopts
  // the session's document, waits for its first run, re-runs its pins and restores the view.
  Status saveSession(const QString& path) const;
  Status loadSession(const QString& path, const QString& ask = {});
  // Writes the preset with the current values and data.
  Status savePreset(const QString& path) const;
  // The view state (opaque to the engine): one JSON object with a key per registered part (the
  // window's geometry, the zoom, the replay position, ...): `save` gives its value, `restore`
  // takes it back; parts restore in the order added.
  QString viewState() const;
  void restoreViewState(const QString& state);
  void addViewStatePart(const QString& key, std::function<QJsonValue()> save,
                        std::function<void(const QJsonValue&)> restore);

  // Asks before throwing away unsaved changes or pinned snapshots (switching preset, opening a
  // session, quitting); true: go ahead. Tests answer through setConfirmHandler.
  bool confirmDiscard(const QString& action);
  void setConfirmHandler(std::function<bool(const QString&)> handler) {
    confirm_ = std::move(handler);
  }

 signals:
  // A new document (a preset or a session): its controls and plots are to be made.
  void documentReplaced();
  // Values, data or pins changed other than through a control (undo, redo, reset, applied
  // values, a rejected value): show them.
  void changed();
  // The undo history changed (the Undo / Redo actions' state and text).
  void historyChanged();
  // The pins or their runs changed (ghosts and metrics columns).
  void pinsChanged();
  void problem(const QString& message);

 private:
  // After undo / redo / reset / a new mapping: keep the runs of pins still there, show, run.
  void sync();
  // The document's notices (a retired scenario loaded as its model file, dropped keys and view
  // state), shown as one problem.
  void showNotices(const std::vector<std::string>& notices);

  RunController* runs_;
  QWidget* window_;
  std::unique_ptr<Document> doc_;
  std::vector<Pin> pins_;
  std::vector<AdoptStep> steps_;
  std::string last_edit_key_;  // slider drags join one undo step
  QElapsedTimer last_edit_;
  std::function<bool(const QString&)> confirm_;  // empty: a message box asks
  struct ViewPart {
    QString key;
    std::function<QJsonValue()> save;
    std::function<void(const QJsonValue&)> restore;
  };
  std::vector<ViewPart> view_parts_;
};

}  // namespace kfw
