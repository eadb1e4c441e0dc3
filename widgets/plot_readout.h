// The readout: a vertical cursor line across every time plot at the mouse's time, and beside it
// on the hovered plot the values of its visible curves at that time; on a heat map or a curve
// over a parameter, the value under the mouse. Drawn on a buffered layer of its own, so following
// the mouse replots that layer only.
#pragma once

#include <QList>
#include <QObject>
#include <QPair>
#include <QPointF>
#include <QString>
#include <vector>

#include "scenario_view.h"

class QCustomPlot;
class QCPGraph;
class QCPItemStraightLine;
class QCPItemText;
class QCPLayer;

namespace kfw::plot {

// The value of a graph at key t: the source sample at or before t (exact for a reduced series),
// or, without a source, the graph's own last point at or before t; NaN before its first point.
double valueAt(const QCPGraph* g, double t);
// The values of every visible named curve of p at key t; a band gives "name" with its lower
// and upper edge as two entries "name (low)", "name (high)".
QList<QPair<QString, double>> curveValuesAt(const QCustomPlot* p, double t);

class PlotReadout final : public QObject {
  Q_OBJECT
 public:
  PlotReadout(const QList<PlotPanel>& plots, QObject* parent);

  // A time cursor at t on every time plot, the values on `hovered` (null: on none).
  void showTime(double t, QCustomPlot* hovered);
  // The value under the pixel `pos` of a plot whose x axis is not time.
  void showPoint(QCustomPlot* p, const QPointF& pos);
  void mouseMoved(QCustomPlot* p, const QPointF& pos);
  void hide();
  // The text shown on p (empty when none), for tests.
  QString text(const QCustomPlot* p) const;

 private:
  struct Marks {
    QCustomPlot* plot = nullptr;
    QCPLayer* layer = nullptr;
    QCPItemStraightLine* line = nullptr;
    QCPItemText* label = nullptr;
  };
  Marks* find(const QCustomPlot* p);
  void place(Marks& m, const QString& text, double x_px);
  std::vector<Marks> marks_;
};

}  // namespace kfw::plot
