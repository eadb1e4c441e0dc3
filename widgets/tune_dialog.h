// Auto-tune from the GUI: pick parameters and an objective, watch progress, cancel, and write the
// result back to the sliders. The search itself is the engine's kfw::tune, on a worker thread.
#pragma once

#include <QDialog>
#include <QFutureWatcher>
#include <atomic>
#include <memory>

#include "core/scenario.h"
#include "core/tuning.h"

class QComboBox;
class QProgressBar;
class QPushButton;
class QLabel;
class QCheckBox;

namespace kfw {

class TuneDialog : public QDialog {
  Q_OBJECT
 public:
  TuneDialog(std::shared_ptr<const Scenario> scenario, std::shared_ptr<const Dataset> dataset,
             const ParamValues& start, QWidget* parent = nullptr);
  ~TuneDialog() override;

  // Starts the search (also what the Run button does). Finishes with finished().
  void start();
  void cancel();
  bool running() const { return watcher_.isRunning(); }
  QString message() const;
  void setObjective(const QString& name);
  void setSelected(const QStringList& keys);

 signals:
  // The best values found (every key); the main window writes them to the sliders.
  void tuned(const kfw::ParamValues& values);

 private:
  std::shared_ptr<const Scenario> scenario_;
  std::shared_ptr<const Dataset> data_;
  ParamValues start_;
  QList<QCheckBox*> checks_;
  QComboBox* objective_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QPushButton *run_ = nullptr, *cancel_ = nullptr;
  QLabel* result_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  std::shared_ptr<std::atomic<int>> evals_;
  QFutureWatcher<Expected<TuneResult>> watcher_;
  QString objective_name_;
};

}  // namespace kfw
