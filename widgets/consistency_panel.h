// The consistency panel, the same for every scenario: per channel, NIS with two-sided χ² bounds
// (per step and as a moving average), the innovations' autocorrelation with ±1.96/√N and a
// Ljung–Box p-value, and NEES with χ² bounds when truth is present. It reads
// RunResult::channels() / nees_series() and calls the engine's statistics.
#pragma once

#include <QList>
#include <QWidget>
#include <memory>

#include "core/scenario.h"
#include "plot_export.h"
#include "scenario_view.h"

class QComboBox;
class QSpinBox;
class QLabel;
class QCustomPlot;
class QCPGraph;
class QCPBars;
class QCPTextElement;

namespace kfw {

class ConsistencyPanel : public QWidget {
  Q_OBJECT
 public:
  explicit ConsistencyPanel(QWidget* parent = nullptr);
  // A new run; drawn now if visible, else when shown.
  void setResult(std::shared_ptr<const RunResult> result);
  void setWindow(int updates);
  void setChannel(int index);
  QList<PlotPanel> plots() const;
  // What an export writes: per channel its NIS plot (consistency_nis.<channel>) and, for a scalar
  // channel, its whiteness plot (consistency_whiteness.<channel>); NEES once when truth is there.
  // Each item draws its channel first; setChannel(channel()) afterwards shows the user's again.
  QList<ExportItem> exportItems();
  int channel() const;
  QString summary() const;
  // Draws now (exports call this for a hidden panel).
  void refresh();

 protected:
  void showEvent(QShowEvent* e) override;

 private:
  // Copies the channels and NEES out of the result and lists the channels (once per result).
  void load();
  std::shared_ptr<const RunResult> result_;
  std::vector<InnovationChannel> channels_;
  NeesSeries nees_;
  bool dirty_ = false;
  bool loaded_ = true;
  QComboBox* channel_ = nullptr;
  QSpinBox* window_ = nullptr;
  QLabel* summary_ = nullptr;
  QCustomPlot *nis_ = nullptr, *acf_ = nullptr, *nees_plot_ = nullptr;
  QCPTextElement *nis_title_ = nullptr, *acf_title_ = nullptr;
  QCPGraph *nis_y_ = nullptr, *nis_avg_ = nullptr, *nis_lo_ = nullptr, *nis_hi_ = nullptr,
           *avg_lo_ = nullptr, *avg_hi_ = nullptr;
  QCPBars* acf_bars_ = nullptr;
  QCPGraph *acf_lo_ = nullptr, *acf_hi_ = nullptr;
  std::vector<QCPGraph*> acf_lines_;  // every scalar channel, when a vector channel is picked
  QCPGraph *nees_y_ = nullptr, *nees_avg_ = nullptr, *nees_lo_ = nullptr, *nees_hi_ = nullptr;
};

}  // namespace kfw
