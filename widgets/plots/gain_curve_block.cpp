// The gain_curve block: steady-state quantities (gain entries, derived scalars) against a derived
// scalar or the swept parameter — seed 000's k1(β) and p11⁻/N_θ against β (Fig. 3) — with the
// live operating point and a note of its numbers. The curve is the engine's (gain_curve_of).
#include <qcustomplot.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "experiment/gain_curve.h"
#include "gain_curve_plot.h"
#include "plot_kit.h"
#include "plot_text.h"
#include "plots/block_drawer.h"

namespace kfw::plot {

namespace {

class GainCurveBlock final : public BlockDrawer {
 public:
  GainCurveBlock(QWidget* parent, const model::PlotBlockSpec& b, const Scenario& s) : block_(b) {
    entries_ = b.y;
    entries_.insert(entries_.end(), b.y2.begin(), b.y2.end());
    std::vector<std::string> labels[2], units[2];
    QString fallback = "Steady state";
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      model::PlotLine& l = entries_[e];
      if (l.key.rfind("K.", 0) == 0) {  // a gain entry: K[state, role] in [state]/[role]
        l.label = gainEntryLabel(l.key).toStdString();
        l.unit = describe_metric(s, l.key).unit;
      }
      labels[right(e)].push_back(l.label);
      units[right(e)].push_back(l.unit);
      fallback += (e == 0 ? " " : ", ") + symbolOf(l.label);
    }
    title_ = panelTitle(b.title, fallback + " vs " + symbolOf(b.x.label));
    plot_ = makePlot(parent, title_, withUnit(QString::fromStdString(b.x.label), b.x.unit),
                     axisLabel(labels[0], units[0]));
    if (b.log_x) setLog(plot_->xAxis);
    if (b.log_y) setLog(plot_->yAxis);
    // One entry on an axis: the axis label carries its unit; several: only when they share it.
    const bool shared = labels[0].size() == 1 || sameUnit(units[0]);
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      const QColor c = color::cycle(static_cast<int>(e));
      const model::PlotLine& l = entries_[e];
      graphs_.push_back(
          right(e) ? addGraphRight(plot_, legendName(l.label, l.unit, true), c,
                                   axisLabel(labels[1], units[1]))
                   : addGraph(plot_, legendName(l.label, l.unit, shared), c, Style::kLine, 1.5));
    }
    if (b.log_y2) setLog(plot_->yAxis2);
    addOperatingPoints();
    note_ = addNote(plot_);
  }

  QCustomPlot* plot() const override { return plot_; }
  QString title() const override { return title_; }

  void setResult(const BlockInput& in) override {
    std::vector<std::string> keys;
    for (const auto& e : entries_)
      keys.push_back(e.key);
    const std::string x_key = block_.x.key == block_.sweep ? std::string() : block_.x.key;
    auto c = curve(in, keys, x_key);
    for (QCPGraph* g : graphs_)
      g->data()->clear();
    for (QCPGraph* g : ops_)
      g->data()->clear();
    if (!c) {
      note_->setText("No gain curve: " + QString::fromStdString(c.error()));
      replot(plot_);
      return;
    }
    const std::vector<double>& x = x_key.empty() ? c->x : c->x_metric;
    const double x_op = x_key.empty() ? c->at_x : c->steady.at(x_key);
    QString note = symbolOf(block_.x.label) + " = " + noteNumber(x_op);
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      setPoints(graphs_[e], x, c->values[e]);
      if (block_.operating_point && std::isfinite(x_op) && std::isfinite(c->at[e]))
        ops_[e]->addData(x_op, c->at[e]);
      note += "   " + symbolOf(entries_[e].label) + " = " + noteNumber(c->at[e]);
    }
    if (!x_key.empty()) {
      note +=
          QString("\nat %1 = %2").arg(QString::fromStdString(block_.sweep), noteNumber(c->at_x));
    }
    note_->setText(note);
    fit();
    replot(plot_);
  }

 private:
  int right(std::size_t e) const { return e < block_.y.size() ? 0 : 1; }

  // The curve does not depend on the swept parameter's value: while only it changes (dragging Q
  // along the curve), the points are the last curve's and the engine's steady state at the values
  // gives the operating point (one gain() instead of 100). The data count through their time
  // span and rows (dt), the simulator's values through the key.
  Expected<GainCurve> curve(const BlockInput& in, const std::vector<std::string>& keys,
                            const std::string& x_key) {
    ParamValues key = in.values;
    key.erase(block_.sweep);
    std::array<double, 3> data{};
    if (in.data && in.data->rows() > 0 && in.data->has("t")) {
      const auto& t = in.data->col("t");
      data = {static_cast<double>(t.size()), t.front(), t.back()};
    }
    if (cached_ && cache_key_ == key && cache_data_ == data) {
      auto here = in.scenario.gain(in.values, in.data);
      if (here) {
        GainCurve c = *cached_;
        c.steady = *here;
        c.at_x = in.values.at(block_.sweep);
        for (std::size_t e = 0; e < c.entries.size(); ++e) {
          const auto it = here->find(c.entries[e]);
          c.at[e] = it == here->end() ? std::nan("") : it->second;
        }
        return c;
      }
    }
    auto c = gain_curve_of(in.scenario, in.values, block_.sweep, keys, x_key, 100, in.data,
                           block_.range_lo, block_.range_hi);
    cached_.reset();
    if (c) cached_ = *c, cache_key_ = std::move(key), cache_data_ = data;
    return c;
  }

  // Every point of the curve (100, spaced in the swept parameter, not in x: setSeries' raster
  // reduction, made for time series, would merge them), a gap where there is no steady state.
  static void setPoints(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y) {
    QVector<QCPGraphData> data;
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
      if (std::isfinite(x[i]) && std::isfinite(y[i])) data.push_back(QCPGraphData(x[i], y[i]));
    }
    std::sort(data.begin(), data.end(), qcpLessThanSortKey<QCPGraphData>);
    g->data()->set(data, true);
  }

  // The operating point of each curve, added last so that it is drawn over the curves; one
  // legend entry for them all.
  void addOperatingPoints() {
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      QCPGraph* op = plot_->addGraph(plot_->xAxis, right(e) ? plot_->yAxis2 : plot_->yAxis);
      op->setLineStyle(QCPGraph::lsNone);
      const QColor c = e == 0 ? color::kSecond : color::cycle(static_cast<int>(e));
      op->setScatterStyle(
          QCPScatterStyle(e == 0 ? QCPScatterStyle::ssCircle : QCPScatterStyle::ssDiamond,
                          QPen(c, 2), QBrush(c), 9));
      op->setName(e == 0 ? "operating point" : "");
      if (e > 0 || !block_.operating_point) op->removeFromLegend();
      ops_.push_back(op);
    }
  }

  // The axes to the curves and their operating points, unless the user zoomed: a margin of
  // `frac` of the span on each side (in decades on a log axis).
  static void fitAxis(QCPAxis* a, double frac) {
    a->rescale();
    const QCPRange r = a->range();
    if (a->scaleType() == QCPAxis::stLogarithmic) {
      if (!(r.lower > 0.0 && r.upper > r.lower)) return;
      const double f = std::pow(r.upper / r.lower, frac);
      a->setRange(r.lower / f, r.upper * f);
    } else {
      const double m = frac * std::max(r.size(), 1e-12 * std::abs(r.center()) + 1e-300);
      a->setRange(r.lower - m, r.upper + m);
    }
  }

  void fit() {
    if (!userZoomedX(plot_)) fitAxis(plot_->xAxis, 0.02);
    if (userZoomedY(plot_)) return;
    fitAxis(plot_->yAxis, 0.05);
    if (!block_.y2.empty()) fitAxis(plot_->yAxis2, 0.05);
  }

  model::PlotBlockSpec block_;
  std::vector<model::PlotLine> entries_;  // y then y2, gain entries' labels and units resolved
  std::optional<GainCurve> cached_;       // the last curve, for the values in cache_key_
  ParamValues cache_key_;                 // those values but the swept and simulator keys
  std::array<double, 3> cache_data_{};    // rows, first and last time of the data
  QString title_;
  QCustomPlot* plot_ = nullptr;
  std::vector<QCPGraph*> graphs_, ops_;
  QCPItemText* note_ = nullptr;
};

}  // namespace

std::unique_ptr<BlockDrawer> makeGainCurveBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                const Scenario& s) {
  return std::make_unique<GainCurveBlock>(parent, b, s);
}

}  // namespace kfw::plot
