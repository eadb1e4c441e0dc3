// A metric over one parameter (a curve) or two (a heat map), from the engine's kfw::sweep on both
// cores — e.g. seed 000 Fig. 8 (RMS error vs γ) or Fig. 7 (√(P11/N_θ) vs m).
#pragma once

#include <QDialog>
#include <QFutureWatcher>
#include <atomic>
#include <memory>

#include "core/scenario.h"
#include "core/tuning.h"

class QComboBox;
class QDoubleSpinBox;
class QSpinBox;
class QLabel;
class QPushButton;
class QCustomPlot;

namespace kfw {

class SweepDialog : public QDialog {
  Q_OBJECT
 public:
  SweepDialog(std::shared_ptr<const Scenario> scenario, std::shared_ptr<const Dataset> dataset,
              const ParamValues& base, const Metrics& metrics, QWidget* parent = nullptr);
  ~SweepDialog() override;

  // Sets an axis: 0 = x, 1 = y (key empty = no y axis).
  void setAxis(int which, const QString& key, double lo, double hi, int n);
  void setMetric(const QString& name);
  void start();
  bool running() const { return watcher_.isRunning(); }
  QCustomPlot* plot() const { return plot_; }
  QString message() const;

 signals:
  void done();

 private:
  struct AxisUi {
    QComboBox* key = nullptr;
    QDoubleSpinBox *lo = nullptr, *hi = nullptr;
    QSpinBox* n = nullptr;
  };
  void showResult(const SweepResult& r, const QString& metric);

  std::shared_ptr<const Scenario> scenario_;
  std::shared_ptr<const Dataset> data_;
  ParamValues base_;
  AxisUi axes_[2];
  QComboBox* metric_ = nullptr;
  QPushButton* run_ = nullptr;
  QLabel* status_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  QFutureWatcher<Expected<SweepResult>> watcher_;
  QString running_metric_;
};

}  // namespace kfw
