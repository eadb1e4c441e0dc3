// Auto-tune from the GUI: the preset's tunable keys with their search bounds, an objective by
// the metric declarations (or rmse+nis / rmse+anis), the NLopt method, budget and tolerance, a
// tuning set of several logs; progress and Cancel; the result shown with what the objective could
// not determine and any bound it sits on; Apply keeps it, Revert restores the start. The search is
// the engine's kfw::tune on a worker thread.
#pragma once

#include <QDialog>
#include <QFutureWatcher>
#include <atomic>
#include <memory>

#include "core/scenario.h"
#include "document/preset.h"
#include "experiment/tuning.h"

class QComboBox;
class QProgressBar;
class QPushButton;
class QLabel;
class QCheckBox;
class QLineEdit;
class QSpinBox;
class QListWidget;

namespace kfw {

class TuneDialog : public QDialog {
  Q_OBJECT
 public:
  // `probe`: the current run (which metrics exist); `dataset`: the current dataset, the first
  // log of the tuning set.
  TuneDialog(const Preset& preset, std::shared_ptr<const Dataset> dataset, const QString& name,
             std::shared_ptr<const RunResult> probe, const ParamValues& start,
             QWidget* parent = nullptr);
  ~TuneDialog() override;

  // Starts the search (also what the Run button does). Finishes with tuned().
  void start();
  void cancel();
  bool running() const { return watcher_.isRunning(); }
  QString message() const;
  QString objective() const;
  void setObjective(const QString& name);
  void setSelected(const QStringList& keys);
  QStringList selected() const;
  void setBounds(const QString& key, double lo, double hi);
  void setBudget(int evaluations);
  // Adds a CSV to the tuning set (read through the preset's mapping); the message names the
  // file and line on an error.
  Status addLog(const QString& path);
  QStringList logs() const;
  // Keeps the result (closes) / restores the values the dialog started from.
  void apply();
  void revert();
  int progressValue() const;
  int progressMaximum() const;
  const TuneResult* result() const { return result_ ? &*result_ : nullptr; }

 signals:
  // The best values found (every key): the main window applies them as one undo step.
  void tuned(const kfw::ParamValues& values);
  // Revert: the values the dialog started from.
  void reverted(const kfw::ParamValues& values);
  // The files of the tuning set (beyond the current dataset) changed.
  void tuningSetChanged(const QStringList& paths);

 private:
  struct KeyUi {
    std::string key;
    QCheckBox* check = nullptr;
    QLineEdit *lo = nullptr, *hi = nullptr;
    SearchParam param;
  };
  void finished();

  Preset preset_;
  std::shared_ptr<const Scenario> scenario_;
  std::vector<std::pair<QString, std::shared_ptr<const Dataset>>> logs_;
  std::shared_ptr<const RunResult> probe_;
  ParamValues start_;
  std::vector<KeyUi> keys_;
  QComboBox *objective_ = nullptr, *method_ = nullptr, *aggregate_ = nullptr;
  QSpinBox* budget_ = nullptr;
  QLineEdit* tol_ = nullptr;
  QListWidget* log_list_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QPushButton *run_ = nullptr, *cancel_ = nullptr, *apply_ = nullptr, *revert_ = nullptr;
  QLabel* result_label_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  std::shared_ptr<std::atomic<int>> evals_;
  QFutureWatcher<Expected<TuneResult>> watcher_;
  TuneObjective running_objective_;
  std::optional<TuneResult> result_;
};

}  // namespace kfw
