// The runs: re-runs the scenario off the GUI thread whenever parameters change (bursts coalesce:
// while a run is in flight only the latest request is kept, and it starts when the run returns),
// keeps the latest result, knows when the latest request has landed and been drawn (tests,
// exports and sessions wait for that), and opens the experiment dialogs (Tune, Sweep, Monte
// Carlo) over the current dataset; their results come back as signals for the document.
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <QStringList>
#include <QThreadPool>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "core/dataset.h"
#include "core/param_spec.h"
#include "core/scenario.h"
#include "document/preset.h"

class QWidget;

namespace kfw {

class MonteCarloDialog;
class SweepDialog;
class TuneDialog;

class RunController : public QObject {
  Q_OBJECT
 public:
  explicit RunController(QObject* parent = nullptr);
  ~RunController() override;

  // A new scenario drops the simulated-data cache, any pending request and the last result.
  void setScenario(std::shared_ptr<const Scenario> scenario);
  std::shared_ptr<const Scenario> scenario() const { return scenario_; }
  // Data from a file; nullptr switches back to simulated data (from the sim.* parameters).
  void setFileDataset(std::shared_ptr<const Dataset> data);
  bool usesFile() const { return static_cast<bool>(file_); }
  // The dataset of the last finished run (file or simulated).
  std::shared_ptr<const Dataset> dataset() const { return last_dataset_; }
  // The last finished run's result; null until one (and after setScenario).
  std::shared_ptr<const RunResult> result() const { return result_; }

  // Asks for a run with these values; coalesced, latest wins.
  void request(const ParamValues& values);
  bool busy() const { return busy_; }
  // The wall time of simulate + filter in the last finished run.
  double lastWallMs() const { return last_wall_ms_; }

  // Settled: the latest request's run has finished (or failed) and every receiver of finished()
  // has drawn it. The latency is request → drawn, of the last settled run.
  bool settled() const { return settled_; }
  double lastLatencyMs() const { return last_latency_ms_; }
  // The exit code of the last settled request: 0 when it ran, else its Error's (2: refused
  // before any work, 1: the run broke down) — what kfw-cli exits with for the same input.
  int lastExitCode() const { return last_exit_code_; }
  double sinceRequestMs() const { return static_cast<double>(since_request_.nsecsElapsed()) / 1e6; }
  // Background drawing that waitSettled() also waits for (the view's gain curve); it signals
  // drawingFinished() when done.
  void setDrawing(std::function<bool()> busy) { drawing_ = std::move(busy); }
  // Sleeps in event loops until settled, nothing runs and nothing draws; false on timeout.
  bool waitSettled(int timeout_ms = 20000);

  // The experiment dialogs (non-modal, deleted on close) on the last run's dataset: null when
  // there is none yet. `values` are the document's; `data_name` names the dataset for the user.
  TuneDialog* openTune(const Preset& preset, const ParamValues& values, const QString& data_name,
                       const std::vector<DataRef>& tuning_set, QWidget* parent);
  SweepDialog* openSweep(const ParamValues& values, QWidget* parent);
  // Monte Carlo simulates each seed: refused (with a message box) while the data come from a file.
  MonteCarloDialog* openMonteCarlo(const ParamValues& values, QWidget* parent);

 signals:
  // The run for `values` finished; `ms` is the wall time of simulate + filter in the worker.
  // Receivers draw it before returning; applied() follows.
  void finished(std::shared_ptr<const kfw::RunResult> result, const kfw::ParamValues& values,
                double ms);
  void failed(const QString& message);
  // After the receivers of finished() (ok) or failed() (not ok) returned; settled() tells
  // whether this was the latest request.
  void applied(bool ok);
  // A request was made (a run will follow).
  void requested();
  // The background drawing of setDrawing() finished (wakes waitSettled).
  void drawingFinished();
  // From the experiment dialogs: values to apply as one named undo step (a tuning, its revert, a
  // sweep point); the tuned objective's metric (shown first); the tuning set's files; a problem.
  void valuesChosen(const kfw::ParamValues& values, const QString& label);
  void objectiveChosen(const QString& metric_key);
  void tuningSetChosen(const QStringList& paths);
  void problem(const QString& message);

 private:
  struct Outcome;
  void start(const ParamValues& values);
  void onDone(const std::shared_ptr<Outcome>& out);
  void settle(bool ok);

  QThreadPool pool_;
  std::shared_ptr<const Scenario> scenario_;
  std::shared_ptr<const Dataset> file_;
  std::shared_ptr<const Dataset> sim_cache_;
  ParamValues sim_key_;
  std::shared_ptr<const Dataset> last_dataset_;
  std::shared_ptr<const RunResult> result_;
  std::optional<ParamValues> pending_;
  bool busy_ = false;
  double last_wall_ms_ = 0.0;
  int last_exit_code_ = 0;
  std::uint64_t generation_ = 0;
  std::shared_ptr<std::atomic<bool>> cancel_;
  bool settled_ = true;
  QElapsedTimer since_request_;
  double last_latency_ms_ = 0.0;
  std::function<bool()> drawing_;
};

}  // namespace kfw
