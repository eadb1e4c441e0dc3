// Re-runs the scenario off the GUI thread whenever parameters change. Bursts coalesce: while a
// run is in flight only the latest request is kept, and it starts when the run returns.
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <QThreadPool>
#include <atomic>
#include <memory>
#include <optional>

#include "core/dataset.h"
#include "core/param_spec.h"
#include "core/scenario.h"

namespace kfw {

class RunController : public QObject {
  Q_OBJECT
 public:
  explicit RunController(QObject* parent = nullptr);
  ~RunController() override;

  // A new scenario drops the simulated-data cache and any pending request.
  void setScenario(std::shared_ptr<const Scenario> scenario);
  // Data from a file; nullptr switches back to simulated data (from the sim.* parameters).
  void setFileDataset(std::shared_ptr<const Dataset> data);
  bool usesFile() const { return static_cast<bool>(file_); }
  // The dataset of the last finished run (file or simulated).
  std::shared_ptr<const Dataset> dataset() const { return last_dataset_; }

  // Asks for a run with these values; coalesced, latest wins.
  void request(const ParamValues& values);
  bool busy() const { return busy_; }
  // The worker thread's CPU time in the last finished run (simulate + filter + metrics).
  double lastCpuMs() const { return last_cpu_ms_; }
  // Blocks (processing events) until idle with nothing pending; false on timeout.
  bool waitIdle(int timeout_ms);

 signals:
  // The run for `values` finished; `ms` is the wall time of simulate + filter in the worker.
  void finished(std::shared_ptr<const kfw::RunResult> result, const kfw::ParamValues& values,
                double ms);
  void failed(const QString& message);
  void datasetChanged(std::shared_ptr<const kfw::Dataset> data);

 private:
  struct Outcome;
  void start(const ParamValues& values);
  void onDone(const std::shared_ptr<Outcome>& out);

  QThreadPool pool_;
  std::shared_ptr<const Scenario> scenario_;
  std::shared_ptr<const Dataset> file_;
  std::shared_ptr<const Dataset> sim_cache_;
  ParamValues sim_key_;
  std::shared_ptr<const Dataset> last_dataset_;
  std::optional<ParamValues> pending_;
  bool busy_ = false;
  double last_cpu_ms_ = 0.0;
  std::uint64_t generation_ = 0;
  std::shared_ptr<std::atomic<bool>> cancel_;
};

}  // namespace kfw
