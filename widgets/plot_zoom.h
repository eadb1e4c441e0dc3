// The user's view of a scenario's plots: zoom and pan that survive re-runs and replay ticks, the
// time axes of all time plots linked, box zoom (Ctrl+drag or right-drag), wheel zoom per axis
// (over an axis: that axis; over the data: both), reset to auto by double-click or Home; the
// state saved with the session. Also owns the readout (widgets/plot_readout.h).
#pragma once

#include <QJsonValue>
#include <QList>
#include <QObject>
#include <QPointer>
#include <functional>

#include "scenario_view.h"

class QCustomPlot;
class QTimer;

namespace kfw::plot {

class PlotReadout;

class ZoomGroup final : public QObject {
  Q_OBJECT
 public:
  // `redraw` rebuilds every plot's data (the view at its replay cursor): after a reset, and after
  // a zoom so that lines are reduced for the visible range.
  ZoomGroup(const QList<PlotPanel>& plots, std::function<void()> redraw, QObject* parent);
  ~ZoomGroup() override;

  // Back to auto-range on every plot (Home, double-click).
  void resetAll();
  // Sets the linked time range of every time plot as a user zoom would.
  void zoomTime(double t0, double t1);
  // The same without redrawing the data (replay's following window: the next cursor step
  // redraws them for the new range).
  void followTime(double t0, double t1);
  QJsonValue save() const;
  void restore(const QJsonValue& v);
  PlotReadout* readout() const { return readout_; }

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void userChanged(QCustomPlot* source, bool x, bool y);
  void scheduleRedraw();
  QList<PlotPanel> plots_;
  std::function<void()> redraw_;
  QTimer* redraw_timer_ = nullptr;
  QCustomPlot* interacting_ = nullptr;  // the plot under a mouse gesture, if any
  bool linking_ = false;
  PlotReadout* readout_ = nullptr;
};

}  // namespace kfw::plot
