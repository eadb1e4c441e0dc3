#include "scenarios/model_imm_widgets.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>

#include "plot_kit.h"
#include "plot_text.h"

namespace kfw {

namespace {

constexpr std::size_t kMaxModeLines = 8;
constexpr double kLogMuFloor = -8.0;   // log₁₀ μ below this is drawn as the floor
constexpr std::size_t kMaxTicked = 9;  // up to this many values on a heat-map axis: a tick each

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// How far renewal has moved an axis's grid at step k (0 for a grid that stays).
double shift_at(const model::ImmSeries::Axis& a, std::size_t k) {
  return a.centre.size() > k && std::isfinite(a.centre[k]) ? a.centre[k] - a.centre.front() : 0.0;
}

bool moves(const model::ImmSeries::Axis& a) {
  return std::any_of(a.centre.begin(), a.centre.end(),
                     [&](double c) { return std::isfinite(c) && c != a.centre.front(); });
}

// Ticks at an axis's grid values (moved to step k) for a small grid, the normal ticker otherwise.
void grid_ticks(QCPAxis* axis, const std::vector<double>& values, double shift, int decimals,
                const QSharedPointer<QCPAxisTickerText>& text,
                const QSharedPointer<QCPAxisTicker>& normal) {
  if (values.size() > kMaxTicked) {
    if (axis->ticker() != normal) axis->setTicker(normal);
    return;
  }
  text->clear();
  for (double v : values)
    text->addTick(v + shift, q(model::grid_value_text(v + shift, decimals)));
  if (axis->ticker() != text) axis->setTicker(text);
}

}  // namespace

void ImmPanels::create(QWidget* parent, const ModelLayout& layout, QList<PlotPanel>& out) {
  if (!layout.modes) return;
  lines_ = plot::makePlot(parent, "Mode probabilities μ over time (at most the 8 most probable)",
                          "time (s)", "mode probability μ");
  lines_cursor_ = plot::addCursor(lines_);
  out.push_back({"mode_probabilities", "Mode probabilities", lines_});
  if (layout.grid.size() == 2) {
    const auto& a = layout.grid[0];
    const auto& b = layout.grid[1];
    heat_ = plot::makePlot(parent, "Mode probabilities on the grid at the replay cursor",
                           plot::withUnit(q(a.label), a.unit), plot::withUnit(q(b.label), b.unit));
    heat_->legend->setVisible(false);
    heat_map_ = new QCPColorMap(heat_->xAxis, heat_->yAxis);
    auto* scale = new QCPColorScale(heat_);
    QCPLayoutGrid* grid = heat_->plotLayout();
    int rect_row = 0;
    for (int row = 0; row < grid->rowCount(); ++row) {
      if (grid->element(row, 0) == heat_->axisRect()) rect_row = row;
    }
    grid->addElement(rect_row, 1, scale);
    scale->setType(QCPAxis::atRight);
    scale->axis()->setLabel("log₁₀ μ (–)");
    auto* margins = new QCPMarginGroup(heat_);
    heat_->axisRect()->setMarginGroup(QCP::msBottom | QCP::msTop, margins);
    scale->setMarginGroup(QCP::msBottom | QCP::msTop, margins);
    heat_map_->setColorScale(scale);
    heat_map_->setGradient(QCPColorGradient(QCPColorGradient::gpThermal));
    heat_map_->setInterpolate(false);
    heat_map_->setDataRange(QCPRange(kLogMuFloor, 0.0));
    for (int i = 0; i < 2; ++i) {
      text_ticker_[i].reset(new QCPAxisTickerText);
      text_ticker_[i]->setSubTickCount(0);
      normal_ticker_[i].reset(new QCPAxisTicker);
    }
    info_ = new QCPItemText(heat_);
    info_->setFont(heat_->font());  // not QFont(): the application's, × scale when presenting
    info_->position->setType(QCPItemPosition::ptAxisRectRatio);
    info_->position->setCoords(0.02, 0.03);
    info_->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
    info_->setBrush(QBrush(QColor(255, 255, 255, 210)));
    info_->setPadding(QMargins(4, 2, 4, 2));
    out.push_back({"mode_heatmap", "Mode probabilities on the grid", heat_});
  }
  for (const auto& g : layout.grid) {
    Axis a;
    const QString label = q(g.label);
    a.plot =
        plot::makePlot(parent, QString("IMM estimate of %1 (μ-weighted) and the grid").arg(label),
                       "time (s)", plot::withUnit(label, g.unit));
    // The grid's extent first (a band under the lines), moved by renewal.
    a.envelope = plot::addBand(a.plot, "grid envelope", plot::color::kSensor);
    a.truth = plot::addGraph(a.plot, "truth", plot::color::kTruth, plot::Style::kLine);
    a.estimate = plot::addGraph(a.plot, "IMM estimate Σ μʲ " + plot::typeset(label) + "ʲ",
                                plot::color::kEstimate, plot::Style::kLine);
    a.cursor = plot::addCursor(a.plot);
    out.push_back({q("grid." + g.param), "IMM " + label, a.plot});
    axes_.push_back(a);
  }
}

void ImmPanels::setResult(const model::ModelResult& r) {
  result_ = &r;
  if (!lines_ || !r.imm) return;
  const model::ImmSeries& imm = *r.imm;
  const std::size_t steps = r.steps(), count = imm.modes();
  lines_->clearGraphs();
  graphs_.clear();
  mu_.clear();
  std::vector<double> mean(count, 0.0);
  for (std::size_t k = 0; k < steps; ++k) {
    for (std::size_t j = 0; j < count; ++j) {
      const double m = imm.mu_at(k, j);
      if (std::isfinite(m)) mean[j] += m;
    }
  }
  std::vector<std::size_t> order(count);
  for (std::size_t j = 0; j < count; ++j)
    order[j] = j;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return mean[a] > mean[b]; });
  if (order.size() > kMaxModeLines) order.resize(kMaxModeLines);
  std::sort(order.begin(), order.end());
  line_modes_ = order;
  for (std::size_t j : order) {
    std::vector<double> mu(steps);
    for (std::size_t k = 0; k < steps; ++k)
      mu[k] = imm.mu_at(k, j);
    mu_.push_back(std::move(mu));
    // Colours by the line's place, not the mode's index: 8 lines, 8 different colours.
    graphs_.push_back(plot::addGraph(lines_, q(imm.labels[j]),
                                     plot::color::cycle(static_cast<int>(graphs_.size())),
                                     plot::Style::kLine));
  }
  decimals_.clear();
  moving_ = false;
  for (const auto& a : imm.axes) {
    decimals_.push_back(model::grid_decimals(a.values));
    moving_ = moving_ || moves(a);
  }
  if (heat_map_ && imm.axes.size() == 2) {
    heat_map_->data()->setSize(static_cast<int>(imm.axes[0].n), static_cast<int>(imm.axes[1].n));
  }
  for (std::size_t a = 0; a < axes_.size() && a < imm.axes.size(); ++a) {
    const auto& v = imm.axes[a].values;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    // The grid's ends over time: they move with the centre under renewal.
    const auto& c = imm.axes[a].centre;
    axes_[a].lo_v.assign(steps, *lo);
    axes_[a].hi_v.assign(steps, *hi);
    for (std::size_t k = 0; k < steps && k < c.size() && !c.empty(); ++k) {
      axes_[a].lo_v[k] += c[k] - c.front();
      axes_[a].hi_v[k] += c[k] - c.front();
    }
    // A truth line in the legend only where the axis has a truth column.
    if (imm.axes[a].truth.empty()) {
      axes_[a].truth->removeFromLegend();
    } else {
      axes_[a].truth->addToLegend();
    }
  }
}

void ImmPanels::draw(const plot::Frame& f, std::size_t index) {
  if (!lines_ || !result_ || !result_->imm) return;
  const model::ModelResult& r = *result_;
  for (std::size_t g = 0; g < graphs_.size(); ++g)
    plot::setSeries(graphs_[g], r.t, mu_[g], f.n);
  if (moving_) nameLinesAt(std::min(index, r.steps() - 1));
  plot::rescale(lines_, f.t0, f.t1, f.settle());
  lines_->yAxis->setRange(0.0, 1.0);
  plot::setCursorAt(lines_cursor_, f.tc, !f.all);
  plot::replot(lines_);
  if (heat_map_) drawHeatMap(std::min(index, r.steps() - 1));
  for (std::size_t a = 0; a < axes_.size() && a < r.imm->axes.size(); ++a) {
    const auto& axis = r.imm->axes[a];
    Axis& p = axes_[a];
    plot::setSeries(p.estimate, r.t, axis.estimate, f.n);
    if (!axis.truth.empty()) {
      plot::setSeries(p.truth, r.t, axis.truth, f.n);
    } else {
      p.truth->data()->clear();
    }
    plot::setBandLimits(p.envelope, r.t, p.lo_v, p.hi_v, f.n);
    for (std::size_t g = 0; g < p.ghosts.size() && g < ghosts_.size(); ++g) {
      const auto& gt = ghosts_[g]->t;
      plot::setSeries(p.ghosts[g], gt, ghosts_[g]->imm->axes[a].estimate,
                      f.all ? gt.size() : plot::stepsUpTo(gt, f));
    }
    plot::rescale(p.plot, f.t0, f.t1, f.settle());
    plot::setCursorAt(p.cursor, f.tc, !f.all);
    plot::replot(p.plot);
  }
}

// Each pinned run's estimate of each axis, faded, as "estimate [pinned: NAME]" (runs of the same
// grid axes only).
void ImmPanels::setSnapshots(
    const std::vector<std::pair<QString, std::shared_ptr<const model::ModelResult>>>& pins) {
  ghosts_.clear();
  for (Axis& a : axes_) {
    for (QCPGraph* g : a.ghosts)
      a.plot->removeGraph(g);
    a.ghosts.clear();
  }
  int colour = 0;
  for (const auto& [name, r] : pins) {
    if (!r || !r->imm || r->imm->axes.size() != axes_.size()) continue;
    ghosts_.push_back(r);
    for (Axis& a : axes_)
      a.ghosts.push_back(plot::addGhost(a.plot, "estimate [pinned: " + name + "]", colour));
    ++colour;
  }
}

// Under renewal a mode stands for its grid value moved to the shown step: the legend says which
// value, and when.
void ImmPanels::nameLinesAt(std::size_t k) {
  const model::ImmSeries& imm = *result_->imm;
  for (std::size_t g = 0; g < graphs_.size(); ++g) {
    const std::size_t j = line_modes_[g];
    QString name;
    for (std::size_t a = 0; a < imm.axes.size(); ++a) {
      const auto& axis = imm.axes[a];
      if (j >= axis.values.size()) return;
      name += (a ? ", " : "") + q(axis.label) + " = " +
              q(model::grid_value_text(axis.values[j] + shift_at(axis, k), decimals_[a]));
    }
    graphs_[g]->setName(plot::typeset(name) +
                        QString(" at t = %1 s").arg(result_->t[k], 0, 'f', 1));
  }
}

// The heat map's note at step k: the time, the most probable mode and its values, the IMM
// estimate of each axis and, where both axes have one, the truth.
QString ImmPanels::heatInfo(std::size_t k) const {
  const model::ImmSeries& imm = *result_->imm;
  std::size_t best = 0;
  double top = -1.0;
  for (std::size_t j = 0; j < imm.modes(); ++j) {
    const double m = imm.mu_at(k, j);
    if (m > top) top = m, best = j;
  }
  const auto pair = [&](double a, double b) {
    return QString("(%1, %2)")
        .arg(q(model::grid_value_text(a, decimals_[0])),
             q(model::grid_value_text(b, decimals_[1])));
  };
  const auto& a = imm.axes[0];
  const auto& b = imm.axes[1];
  QString text = QString("t = %1 s   ").arg(result_->t[k], 0, 'f', 2);
  text += top >= 0.0
              ? QString("max μ = %1 at %2")
                    .arg(top, 0, 'f', 3)
                    .arg(pair(a.values[best] + shift_at(a, k), b.values[best] + shift_at(b, k)))
              : QString("no μ");
  text += "\nestimate " + pair(a.estimate[k], b.estimate[k]);
  if (a.truth.size() > k && b.truth.size() > k) text += "   truth " + pair(a.truth[k], b.truth[k]);
  return text;
}

// μ on the grid at step k: cell (i₀, i₁) is mode i₀ + n₀ i₁ (the first axis fastest).
void ImmPanels::drawHeatMap(std::size_t k) {
  const model::ImmSeries& imm = *result_->imm;
  QCPColorMapData* d = heat_map_->data();
  const int n0 = d->keySize(), n1 = d->valueSize();
  if (n0 < 1 || n1 < 1 || static_cast<std::size_t>(n0 * n1) != imm.modes()) return;
  const auto& v0 = imm.axes[0].values;
  const auto& v1 = imm.axes[1].values;
  // The grid at step k: moved by renewal from its first values.
  const double s0 = shift_at(imm.axes[0], k), s1 = shift_at(imm.axes[1], k);
  const double a0 = v0.front() + s0, a1 = v0[static_cast<std::size_t>(n0 - 1)] + s0;
  const double b0 = v1.front() + s1, b1 = v1.back() + s1;
  d->setRange(QCPRange(a0, a1 > a0 ? a1 : a0 + 1e-9), QCPRange(b0, b1 > b0 ? b1 : b0 + 1e-9));
  for (int i1 = 0; i1 < n1; ++i1) {
    for (int i0 = 0; i0 < n0; ++i0) {
      const double mu = imm.mu_at(k, static_cast<std::size_t>(i0 + n0 * i1));
      d->setCell(i0, i1, std::isfinite(mu) ? std::log10(std::max(mu, 1e-8)) : kLogMuFloor);
    }
  }
  const double h0 = n0 > 1 ? (a1 - a0) / (2.0 * (n0 - 1)) : 0.5 * std::max(std::abs(a0), 1e-3);
  const double h1 = n1 > 1 ? (b1 - b0) / (2.0 * (n1 - 1)) : 0.5 * std::max(std::abs(b0), 1e-3);
  const std::vector<double> g0(v0.begin(), v0.begin() + n0);  // the first axis varies fastest
  std::vector<double> g1;
  for (int i1 = 0; i1 < n1; ++i1)
    g1.push_back(v1[static_cast<std::size_t>(i1 * n0)]);
  grid_ticks(heat_->xAxis, g0, s0, decimals_[0], text_ticker_[0], normal_ticker_[0]);
  grid_ticks(heat_->yAxis, g1, s1, decimals_[1], text_ticker_[1], normal_ticker_[1]);
  info_->setText(heatInfo(k));
  if (!plot::userZoomedX(heat_)) heat_->xAxis->setRange(a0 - h0, a1 + h0);
  if (!plot::userZoomedY(heat_)) heat_->yAxis->setRange(b0 - h1, b1 + h1);
  plot::replot(heat_);
}

}  // namespace kfw
