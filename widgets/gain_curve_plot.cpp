#include "gain_curve_plot.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "plot_blocks.h"
#include "plot_kit.h"
#include "plot_text.h"

namespace kfw::plot {

QString gainEntryLabel(const std::string& entry) {
  // gain() names entries K.<state>.<role>; a state is an identifier, so its name has no dot.
  const std::string rest = entry.rfind("K.", 0) == 0 ? entry.substr(2) : entry;
  const auto dot = rest.find('.');
  if (dot == std::string::npos) return QString::fromStdString(entry);
  return QString("K[%1, %2]")
      .arg(QString::fromStdString(rest.substr(0, dot)),
           QString::fromStdString(rest.substr(dot + 1)));
}

QString gainEntryLabel(const std::string& entry, const std::string& unit) {
  return QString("%1 (%2)").arg(gainEntryLabel(entry),
                                unit.empty() ? QString("–") : QString::fromStdString(unit));
}

QString gainAxisLabel(const std::vector<std::string>& units) {
  if (units.empty()) return "gain (–)";
  for (const auto& u : units) {
    if (u != units.front()) return "gain (units in the legend)";
  }
  return QString("gain (%1)")
      .arg(units.front().empty() ? QString("–") : QString::fromStdString(units.front()));
}

GainCurvePlot::GainCurvePlot(QWidget* parent) {
  plot_ = makePlot(parent, "Steady-state gain vs a parameter (DARE)", "parameter", "gain (–)");
  label_ = addNote(plot_);
}

void GainCurvePlot::clearGraphs() {
  for (QCPGraph* g : curves_)
    plot_->removeGraph(g);
  curves_.clear();
  if (op_) plot_->removeGraph(op_);
  op_ = nullptr;
}

void GainCurvePlot::setMessage(const QString& message) {
  clearGraphs();
  label_->setText("No gain curve: " + message);
  plot_->xAxis->setScaleType(QCPAxis::stLinear);
  plot_->xAxis->setRange(0, 1);
  plot_->yAxis->setRange(0, 1);
  replot(plot_);
}

void GainCurvePlot::setCurve(const GainCurve& c, const QString& label, const QString& unit) {
  clearGraphs();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t e = 0; e < c.entries.size(); ++e) {
    const QString name = c.units.size() == c.entries.size()
                             ? gainEntryLabel(c.entries[e], c.units[e])
                             : gainEntryLabel(c.entries[e]);
    QCPGraph* g = addGraph(plot_, name, color::cycle(static_cast<int>(e)), Style::kLine, 1.5);
    setSeries(g, c.x, c.values[e], kAll);
    curves_.push_back(g);
    for (double v : c.values[e]) {
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    lo = std::min(lo, c.at[e]);
    hi = std::max(hi, c.at[e]);
  }
  // The operating point, added last so that it is drawn over the curves.
  op_ = addGraph(plot_, "operating point", color::kSecond);
  op_->setLineStyle(QCPGraph::lsNone);
  op_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, QPen(color::kSecond, 2),
                                       QBrush(color::kSecond), 9));
  for (double v : c.at)
    op_->addData(c.at_x, v);

  const QString xname = unit.isEmpty() ? label : QString("%1 (%2)").arg(label, unit);
  plot_->xAxis->setLabel(typeset(xname));
  plot_->yAxis->setLabel(gainAxisLabel(c.units));
  if (c.log) {
    setLog(plot_->xAxis);
  } else {
    plot_->xAxis->setScaleType(QCPAxis::stLinear);
    plot_->xAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
  }
  plot_->xAxis->setRange(c.x.front(), c.x.back());
  if (!(lo <= hi)) lo = 0.0, hi = 1.0;
  if (lo > 0.0) {
    // Positive gains span decades over a log parameter: a log axis keeps the small ones readable.
    setLog(plot_->yAxis);
    plot_->yAxis->setRange(lo / 1.5, hi * 1.5);
  } else {
    plot_->yAxis->setScaleType(QCPAxis::stLinear);
    plot_->yAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
    const double pad = hi > lo ? 0.08 * (hi - lo) : std::max(1e-3, 0.1 * std::abs(hi));
    plot_->yAxis->setRange(lo - pad, hi + pad);
  }

  QString text = QString("%1 = %2").arg(QString::fromStdString(c.key)).arg(c.at_x, 0, 'g', 4);
  for (std::size_t e = 0; e < c.entries.size() && e < 6; ++e) {
    const bool has_unit = c.units.size() == c.entries.size() && !c.units[e].empty();
    text += QString("\n%1 = %2%3")
                .arg(gainEntryLabel(c.entries[e]))
                .arg(c.at[e], 0, 'g', 5)
                .arg(has_unit ? " " + QString::fromStdString(c.units[e]) : QString());
  }
  // The DARE's steady-state standard deviations (P after an update) beside its gain.
  QStringList sigmas;
  for (const auto& [k, v] : c.steady) {
    if (k.rfind("P_post.", 0) == 0 && k.find('.', 7) == std::string::npos && v >= 0.0)
      sigmas << QString("σ∞(%1) = %2")
                    .arg(QString::fromStdString(k.substr(7)))
                    .arg(std::sqrt(v), 0, 'g', 4);
  }
  if (!sigmas.isEmpty()) text += "\n" + sigmas.join("  ");
  label_->setText(text);
  replot(plot_);
}

}  // namespace kfw::plot
