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
  // The mouse left the plots: back to the replay cursor when one is set, else nothing shown.
  void hide();
  // The replay cursor at t (s): while the mouse is over no plot, the cursor line (and with
  // `labels`, the values) of every time plot are those at t. NaN: no replay cursor (the whole
  // run is shown).
  void setReplayTime(double t, bool labels = true);
  double replayTime() const { return replay_t_; }
  // True while the mouse is over a plot's data (the readout follows it, not the replay).
  bool hovering() const { return hovering_; }
  // The text shown on p (empty when none), for tests.
  QString text(const QCustomPlot* p) const;
  // The time (x) of the cursor line shown on p; NaN when none is shown.
  double lineAt(const QCustomPlot* p) const;

 private:
  struct Marks {
    QCustomPlot* plot = nullptr;
    QCPLayer* layer = nullptr;
    QCPItemStraightLine* line = nullptr;
    QCPItemText* label = nullptr;
  };
  Marks* find(const QCustomPlot* p);
  void place(Marks& m, const QString& text, double x_px);
  QString timeText(const QCustomPlot* p, double t) const;
  void showReplay();
  // The time cursor at t on every time plot, labelled on `hovered` (or on all of them).
  void drawTime(double t, const QCustomPlot* hovered, bool label_all);
  void hideAll();
  std::vector<Marks> marks_;
  double replay_t_;
  bool hovering_ = false;
  bool replay_labels_ = true;
};

}  // namespace kfw::plot
