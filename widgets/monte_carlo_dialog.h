// Monte Carlo over simulator seeds in the background (the engine's kfw::run_monte_carlo on every
// core, progress and Cancel): the primary state's error over the seeds (mean ± 2 sd) against the
// filter's ±2σ, and ANEES_k / ANIS_k over time with their 95 % bounds for N runs.
#pragma once

#include <QDialog>
#include <QFutureWatcher>
#include <atomic>
#include <memory>

#include "experiment/monte_carlo.h"

class QLabel;
class QProgressBar;
class QPushButton;
class QSpinBox;
class QCustomPlot;
class QTimer;

namespace kfw {

class MonteCarloDialog : public QDialog {
  Q_OBJECT
 public:
  // `values`: the parameters to run (sim.seed is replaced by each seed).
  MonteCarloDialog(std::shared_ptr<const Scenario> scenario, const ParamValues& values,
                   QWidget* parent = nullptr);
  ~MonteCarloDialog() override;

  void setSeeds(int first, int count);
  void start();
  void cancel();
  bool running() const { return watcher_.isRunning(); }
  QString message() const;
  QCustomPlot* errorPlot() const { return error_plot_; }
  QCustomPlot* consistencyPlot() const { return consistency_plot_; }

 signals:
  void runFinished();  // the run ended (finished, failed or cancelled)

 private:
  void showSummary(const MonteCarloSummary& s);

  std::shared_ptr<const Scenario> scenario_;
  ParamValues values_;
  QSpinBox *first_ = nullptr, *count_ = nullptr;
  QPushButton *run_ = nullptr, *cancel_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* status_ = nullptr;
  QCustomPlot *error_plot_ = nullptr, *consistency_plot_ = nullptr;
  QTimer* poll_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  std::shared_ptr<std::atomic<std::size_t>> done_;
  QFutureWatcher<Expected<MonteCarloPart>> watcher_;
};

}  // namespace kfw
