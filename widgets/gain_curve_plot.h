// The steady-state gain entries versus one parameter, with the live operating point and the
// DARE's gain and covariance in a label: the generalisation of seed 000 Fig. 3 and of the α-β
// curve of seed 003, for any scenario whose gain() reports K entries.
#pragma once

#include <QString>
#include <vector>

#include "experiment/gain_curve.h"

class QCustomPlot;
class QCPGraph;
class QCPItemText;
class QWidget;

namespace kfw::plot {

class GainCurvePlot {
 public:
  explicit GainCurvePlot(QWidget* parent);
  QCustomPlot* plot() const { return plot_; }
  // Draws a computed curve; `unit` and `label` describe its parameter.
  void setCurve(const GainCurve& c, const QString& label, const QString& unit);
  // No steady state (a nonlinear or time-varying model, a failed DARE): the message instead.
  void setMessage(const QString& message);

 private:
  void clearGraphs();
  QCustomPlot* plot_;
  std::vector<QCPGraph*> curves_;
  QCPGraph* op_ = nullptr;
  QCPItemText* label_ = nullptr;
};

// "K.pos.z" → "K[pos, z]"; with its unit, "K[v, z] (1/s)" ("(–)" when dimensionless).
QString gainEntryLabel(const std::string& entry);
QString gainEntryLabel(const std::string& entry, const std::string& unit);
// The gain axis: "gain (1/s)" when every entry has that unit, else "gain (units in the legend)".
QString gainAxisLabel(const std::vector<std::string>& units);

}  // namespace kfw::plot
