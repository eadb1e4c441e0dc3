#include "plot_blocks.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>

#include "core/dataset.h"
#include "core/statistics.h"
#include "filter/consistency.h"

namespace kfw::plot {

Frame frameAt(const std::vector<double>& t, std::size_t index) {
  Frame f;
  const std::size_t steps = t.size();
  f.all = index >= steps;
  f.n = f.all ? steps : index + 1;
  if (steps) {
    f.t0 = t.front();
    f.t1 = t.back();
    f.tc = t[f.n - 1];
  }
  return f;
}

void setLevel(QCPGraph* g, const Frame& f, double y) {
  setSeries(g, {f.t0, f.all ? f.t1 : f.tc}, {y, y}, 2);
}

QCPItemText* addNote(QCustomPlot* p) {
  auto* note = new QCPItemText(p);
  note->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
  note->position->setType(QCPItemPosition::ptAxisRectRatio);
  note->position->setCoords(0.02, 0.03);
  note->setFont(QFont(p->font().family(), 8));
  note->setTextAlignment(Qt::AlignLeft);
  note->setPadding(QMargins(4, 2, 4, 2));
  note->setBrush(QBrush(QColor(255, 255, 255, 210)));
  return note;
}

std::size_t stepsUpTo(const std::vector<double>& t, const Frame& f) {
  if (f.all) return t.size();
  return static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), f.tc) - t.begin());
}

EstimatePlot::EstimatePlot(QWidget* parent, const QString& title, const QString& yLabel,
                           const QString& estimateName, const QString& sensorName,
                           const QString& truthName) {
  plot_ = makePlot(parent, title, "time (s)", yLabel);
  band_ = addBand(plot_, "estimate ± 2σ", color::kEstimate);
  if (!sensorName.isEmpty()) sensor_ = addGraph(plot_, sensorName, color::kSensor, Style::kDots);
  truth_ = addGraph(plot_, truthName, color::kTruth, Style::kLine);
  estimate_ = addGraph(plot_, estimateName, color::kEstimate, Style::kLine);
  cursor_ = addCursor(plot_);
}

void EstimatePlot::setData(const std::vector<double>* t, const std::vector<double>* estimate,
                           const std::vector<double>* variance, const std::vector<double>* truth,
                           const std::vector<double>* sensor) {
  t_ = t;
  x_ = estimate;
  truth_y_ = truth && !truth->empty() ? truth : nullptr;
  sensor_y_ = sensor && !sensor->empty() ? sensor : nullptr;
  variance_ = variance && !variance->empty() ? variance : nullptr;
  // A series with no data leaves the legend (truth of a file without truth, say).
  truth_->setVisible(truth_y_ != nullptr);
  if (truth_y_) {
    truth_->addToLegend();
  } else {
    truth_->removeFromLegend();
  }
  band_.upper->setVisible(variance_ != nullptr);
  band_.lower->setVisible(variance_ != nullptr);
  if (turn_ > 0.0 && t_ && x_) {
    estimate_gapped_ = gap_wraps(*t_, *x_, turn_);
    truth_gapped_ = truth_y_ ? gap_wraps(*t_, *truth_y_, turn_) : GappedSeries{};
    if (variance_) {
      // The band's edges x ± 2σ, broken where the estimate wraps.
      const std::size_t n = std::min(x_->size(), variance_->size());
      std::vector<double> lo(n), hi(n);
      for (std::size_t k = 0; k < n; ++k) {
        const double v = (*variance_)[k];
        const double half = v >= 0.0 ? 2.0 * std::sqrt(v) : std::nan("");
        lo[k] = (*x_)[k] - half;
        hi[k] = (*x_)[k] + half;
      }
      band_gapped_ = gap_band_wraps(*t_, *x_, lo, hi, turn_);
    }
  }
}

void EstimatePlot::setGhosts(const QList<GhostSeries>& ghosts) {
  for (const auto& g : ghosts_)
    removePlottables({g.graph});
  ghosts_.clear();
  int i = 0;
  for (const auto& s : ghosts) {
    if (!s.t || !s.y) continue;
    ghosts_.push_back({s, addGhost(plot_, s.name, i++),
                       turn_ > 0.0 ? gap_wraps(*s.t, *s.y, turn_) : GappedSeries{}});
  }
}

void EstimatePlot::draw(const Frame& f) {
  if (!t_ || !x_) return;
  const std::vector<double>& t = *t_;
  if (sensor_ && sensor_y_) setSeries(sensor_, t, *sensor_y_, f.n);
  if (turn_ > 0.0) {
    // An angle: the series with their wrap gaps, drawn as gaps.
    const GappedBand& b = band_gapped_;
    if (variance_) setBandLimits(band_, b.t, b.lo, b.hi, b.points_for(f.n), true);
    const GappedSeries &e = estimate_gapped_, &tr = truth_gapped_;
    if (truth_y_) setSeries(truth_, tr.t, tr.y, tr.points_for(f.n), false);
    setSeries(estimate_, e.t, e.y, e.points_for(f.n), false);
    for (const auto& g : ghosts_) {
      setSeries(g.graph, g.gapped.t, g.gapped.y, g.gapped.points_for(stepsUpTo(*g.s.t, f)), false);
    }
  } else {
    if (variance_) setSigmaBand(band_, t, x_, *variance_, 2.0, f.n);
    if (truth_y_) setSeries(truth_, t, *truth_y_, f.n);
    setSeries(estimate_, t, *x_, f.n);
    for (const auto& g : ghosts_)
      setSeries(g.graph, *g.s.t, *g.s.y, stepsUpTo(*g.s.t, f));
  }
  rescale(plot_, f.t0, f.t1, f.settle());
  setCursorAt(cursor_, f.tc, !f.all);
  replot(plot_);
}

InnovationPlot::InnovationPlot(QWidget* parent, const QString& title, const QString& yLabel,
                               const QString& innovationName) {
  plot_ = makePlot(parent, title, "time (s)", yLabel);
  band_ = addBand(plot_, "± 2√S", color::kSecond);
  y_ = addGraph(plot_, innovationName, color::kEstimate, Style::kDots);
  cursor_ = addCursor(plot_);
}

void InnovationPlot::setData(const std::vector<double>* t, const std::vector<double>* y,
                             const std::vector<double>* S) {
  t_ = t;
  yv_ = y;
  s_ = S && !S->empty() ? S : nullptr;
}

void InnovationPlot::setRejected(const std::vector<std::size_t>* rows, const QString& name) {
  rows_ = rows && !rows->empty() ? rows : nullptr;
  if (rows_ && !rejected_) {
    rejected_ = addGraph(plot_, name, color::kFourth, Style::kDots);
    rejected_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCross, color::kFourth, 7));
  }
  if (rejected_) {
    rejected_->setName(name);
    rejected_->data()->clear();
    if (rows_) {
      rejected_->addToLegend();
    } else {
      rejected_->removeFromLegend();
    }
  }
}

void InnovationPlot::draw(const Frame& f) {
  if (!t_ || !yv_) return;
  if (s_) setSigmaBand(band_, *t_, nullptr, *s_, 2.0, f.n);
  setSeries(y_, *t_, *yv_, f.n);
  if (rejected_) {
    QVector<QCPGraphData> marks;
    for (std::size_t i = 0; rows_ && i < rows_->size(); ++i) {
      const std::size_t k = (*rows_)[i];
      if (k >= f.n || k >= t_->size() || k >= yv_->size()) break;
      marks.append(QCPGraphData((*t_)[k], (*yv_)[k]));
    }
    rejected_->data()->set(marks, true);
  }
  rescale(plot_, f.t0, f.t1, f.settle());
  setCursorAt(cursor_, f.tc, !f.all);
  replot(plot_);
}

NisPlot::NisPlot(QWidget* parent, const QString& title, std::size_t window) : window_(window) {
  plot_ = makePlot(parent, title, "time (s)", "NIS (–)");
  setLog(plot_->yAxis);
  nis_ = addGraph(plot_, "NIS = yᵀS⁻¹y", color::kEstimate, Style::kDots);
  lo_ = addGraph(plot_, "χ² 2.5 % / 97.5 %", color::kBound, Style::kDashed);
  hi_ = addGraph(plot_, "", color::kBound, Style::kDashed);
  hi_->removeFromLegend();
  avg_ = addGraph(plot_, QString("moving average (%1 updates)").arg(window_), color::kSecond);
  avg_lo_ = addGraph(plot_, "95 % bounds of the average", color::kSecond, Style::kDashed);
  avg_hi_ = addGraph(plot_, "", color::kSecond, Style::kDashed);
  avg_hi_->removeFromLegend();
  cursor_ = addCursor(plot_);
}

void NisPlot::setData(const std::vector<double>* t, const std::vector<double>* nis, double dof,
                      const std::vector<double>* average, std::size_t window) {
  t_ = t;
  nis_y_ = nis;
  lo_v_ = chi2_quantile(0.025, dof);
  hi_v_ = chi2_quantile(0.975, dof);
  if (average && window > 0) {
    avg_src_ = average;
    avg_y_.clear();
    if (window != window_) {
      window_ = window;
      avg_->setName(QString("moving average (%1 updates)").arg(window_));
    }
  } else {
    avg_y_ = nis ? moving_average_finite(*nis, window_) : std::vector<double>{};
    avg_src_ = &avg_y_;
  }
  const auto b = nis_bounds(dof, window_);
  avg_lo_v_ = b.lo;
  avg_hi_v_ = b.hi;
  lo_->setName(QString("χ²(%1) 2.5 % / 97.5 %").arg(dof));
}

void NisPlot::draw(const Frame& f) {
  if (!t_ || !nis_y_) return;
  setSeries(nis_, *t_, *nis_y_, f.n);
  if (avg_src_) setSeries(avg_, *t_, *avg_src_, f.n);
  setLevel(lo_, f, lo_v_);
  setLevel(hi_, f, hi_v_);
  setLevel(avg_lo_, f, avg_lo_v_);
  setLevel(avg_hi_, f, avg_hi_v_);
  rescale(plot_, f.t0, f.t1, f.settle());
  setCursorAt(cursor_, f.tc, !f.all);
  replot(plot_);
}

}  // namespace kfw::plot
