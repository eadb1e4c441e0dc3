// A metric over one parameter (a curve) or two (a heat map), from the engine's kfw::sweep on every
// core — e.g. seed 000 Fig. 8 (RMS error vs γ) or Fig. 7 (√(P11/N_θ) vs m). Progress and Cancel;
// the best point by the metric's declared direction is marked; a click on a point applies it
// (through the main window's undo stack); the grid exports as CSV.
#pragma once

#include <QDialog>
#include <QFutureWatcher>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>

#include "core/scenario.h"
#include "experiment/tuning.h"

class QComboBox;
class QDoubleSpinBox;
class QSpinBox;
class QLabel;
class QPushButton;
class QProgressBar;
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
  // The last sweep's best point by the metric's direction (npos: none), and a point's values.
  std::size_t bestIndex() const { return best_; }
  const SweepResult* result() const { return last_ ? &*last_ : nullptr; }
  // Emits pointChosen with the base values and the point's axis values.
  void choosePoint(std::size_t index);
  // The grid (axes' values and the metric; empty cells where undefined) as CSV, written safely.
  Status exportCsv(const QString& path) const;
  void cancel();
  int progressValue() const;

 signals:
  void runFinished();  // the run ended (finished, failed or cancelled)
  // A point of the grid was clicked: every key's value (the base with the axes' values).
  void pointChosen(const kfw::ParamValues& values);

 private:
  struct AxisUi {
    QComboBox* key = nullptr;
    QDoubleSpinBox *lo = nullptr, *hi = nullptr;
    QSpinBox* n = nullptr;
  };
  void showResult(const SweepResult& r, const QString& metric);
  // What a best point leaves open: on the grid's edge, or in a flat valley (many points within
  // kFlatFraction of it); "" when neither.
  QString sweepWarnings(const SweepResult& r, const std::function<double(std::size_t)>& value,
                        std::size_t best) const;
  static constexpr double kFlatFraction = 0.01;

  std::shared_ptr<const Scenario> scenario_;
  std::shared_ptr<const Dataset> data_;
  ParamValues base_;
  AxisUi axes_[2];
  QComboBox* metric_ = nullptr;
  QPushButton *run_ = nullptr, *cancel_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* status_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  QFutureWatcher<Expected<SweepResult>> watcher_;
  QString running_metric_;
  std::shared_ptr<std::atomic<std::size_t>> done_;
  std::optional<SweepResult> last_;
  MetricSpec spec_;
  std::size_t best_ = static_cast<std::size_t>(-1);
};

}  // namespace kfw
