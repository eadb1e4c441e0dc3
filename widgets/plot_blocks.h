// The plots every filter has, built once: a state's estimate ± 2σ with truth and ghosts, a
// measurement component's innovation ± 2√S, a channel's NIS with χ² bounds. The model view is
// made of them; a scenario view is these blocks plus its own extras.
#pragma once

#include <QColor>
#include <QList>
#include <QString>
#include <cstddef>
#include <vector>

#include "data/wrap_gaps.h"
#include "plot_kit.h"

class QCustomPlot;
class QCPGraph;
class QCPItemStraightLine;
class QCPItemText;
class QWidget;

namespace kfw::plot {

// What replay shows: the first n steps of a run over [t0, t1], the cursor at tc (hidden when all).
struct Frame {
  std::size_t n = 0;
  double t0 = 0.0, t1 = 1.0, tc = 0.0;
  bool all = true;
  double settle() const { return settleTime(t0, t1); }
};
// The frame of a run with times t at replay index `index` (index >= t.size(): everything).
Frame frameAt(const std::vector<double>& t, std::size_t index);

// How many of another run's steps (a ghost's, on its own time base) fall at or before the
// frame's cursor time.
std::size_t stepsUpTo(const std::vector<double>& t, const Frame& f);

// A faded curve of a pinned snapshot: its own time base and values (owned by its result, which
// the view keeps alive).
struct GhostSeries {
  QString name;
  const std::vector<double>* t = nullptr;
  const std::vector<double>* y = nullptr;
};

// Estimate ± 2σ of one state, with truth, an optional sensor series and ghosts.
class EstimatePlot {
 public:
  EstimatePlot(QWidget* parent, const QString& title, const QString& yLabel,
               const QString& estimateName, const QString& sensorName = {},
               const QString& truthName = "truth");
  QCustomPlot* plot() const { return plot_; }
  // The arrays belong to the result the view holds; null leaves a series empty (truth,
  // sensor) or draws no band (variance). The band's half-width 2σ is computed here, once.
  void setData(const std::vector<double>* t, const std::vector<double>* estimate,
               const std::vector<double>* variance, const std::vector<double>* truth,
               const std::vector<double>* sensor = nullptr);
  void setGhosts(const QList<GhostSeries>& ghosts);
  // An angle that wraps every `turn` (2π rad, 360 deg): the estimate, its band, truth and ghosts
  // break where they jump by more than half a turn (engine/data/wrap_gaps.h) instead of drawing
  // a line across the plot. 0 (the default): an ordinary value. Call before setData.
  void setTurn(double turn) { turn_ = turn; }
  // Draws the frame's steps (ghosts up to its cursor time) and replots.
  void draw(const Frame& f);

 private:
  QCustomPlot* plot_;
  Band band_;
  QCPGraph *sensor_ = nullptr, *truth_ = nullptr, *estimate_ = nullptr;
  QCPItemStraightLine* cursor_ = nullptr;
  const std::vector<double>*t_ = nullptr, *x_ = nullptr, *truth_y_ = nullptr, *sensor_y_ = nullptr;
  const std::vector<double>* variance_ = nullptr;
  struct Ghost {
    GhostSeries s;
    QCPGraph* graph;
    GappedSeries gapped;  // an angle's ghost with its wrap gaps
  };
  std::vector<Ghost> ghosts_;
  double turn_ = 0.0;
  GappedSeries estimate_gapped_, truth_gapped_;  // an angle's series with their wrap gaps
  GappedBand band_gapped_;
};

// Innovation y of one measurement component with its ± 2√S band (zero-centred); a measurement
// that did not update is a gap.
class InnovationPlot {
 public:
  InnovationPlot(QWidget* parent, const QString& title, const QString& yLabel,
                 const QString& innovationName);
  QCustomPlot* plot() const { return plot_; }
  // S: the innovation variance of this component (NaN where no update).
  void setData(const std::vector<double>* t, const std::vector<double>* y,
               const std::vector<double>* S);
  // The rows (ascending) whose sample the channel's gate rejected, marked over the innovation
  // under `name`; null or empty: no marks (the legend entry goes with them).
  void setRejected(const std::vector<std::size_t>* rows, const QString& name);
  void draw(const Frame& f);

 private:
  QCustomPlot* plot_;
  Band band_;
  QCPGraph* y_ = nullptr;
  QCPGraph* rejected_ = nullptr;  // made on the first setRejected with rows
  const std::vector<std::size_t>* rows_ = nullptr;
  QCPItemStraightLine* cursor_ = nullptr;
  const std::vector<double>*t_ = nullptr, *yv_ = nullptr;
  const std::vector<double>* s_ = nullptr;
};

// NIS of one channel (dof components) on a log axis with the per-step 95 % χ²(dof) bounds, and a
// moving average over `window` updates with the bounds of such an average.
class NisPlot {
 public:
  NisPlot(QWidget* parent, const QString& title, std::size_t window = 50);
  QCustomPlot* plot() const { return plot_; }
  // `average`: the run's own moving average of the NIS over `window` updates (the plot computes
  // it over its constructor's window when null).
  void setData(const std::vector<double>* t, const std::vector<double>* nis, double dof,
               const std::vector<double>* average = nullptr, std::size_t window = 0);
  void draw(const Frame& f);

 private:
  QCustomPlot* plot_;
  std::size_t window_;
  const std::vector<double>* avg_src_ = nullptr;
  QCPGraph *nis_ = nullptr, *lo_ = nullptr, *hi_ = nullptr, *avg_ = nullptr, *avg_lo_ = nullptr,
           *avg_hi_ = nullptr;
  QCPItemStraightLine* cursor_ = nullptr;
  const std::vector<double>*t_ = nullptr, *nis_y_ = nullptr;
  std::vector<double> avg_y_;
  double lo_v_ = 0.0, hi_v_ = 0.0, avg_lo_v_ = 0.0, avg_hi_v_ = 0.0;
};

// A boxed note in the top-left corner of the axis rect (an operating point's numbers, say).
QCPItemText* addNote(QCustomPlot* p);

// A horizontal line over [t0, tc] as two points (a dashed pen over thousands of vertices is slow
// to stroke).
void setLevel(QCPGraph* g, const Frame& f, double y);

}  // namespace kfw::plot
