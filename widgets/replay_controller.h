// The replay: the transport's cursor drawn by the scenario's view, the transport keys (Space, ←,
// →, Home, End) with any focus in the window but text entry, the following time window applied
// to every time plot, the readout at the replay time when the mouse is over no plot, and the
// replay position in the session's view state.
#pragma once

#include <QJsonValue>
#include <QList>
#include <QObject>
#include <QPointer>
#include <memory>

#include "core/scenario.h"
#include "scenario_view.h"

class QKeyEvent;
class QWidget;

namespace kfw {

class ConsistencyPanel;
class TransportBar;
namespace plot {
class ZoomGroup;
}

class ReplayController : public QObject {
  Q_OBJECT
 public:
  // The keys work in `window` (and its children); `consistency`'s time plots (may be null)
  // follow the time window beside the view's.
  ReplayController(TransportBar* transport, ConsistencyPanel* consistency, QWidget* window);

  TransportBar* transport() const { return transport_; }
  // The view the cursor draws, its plots and their zoom group (whose readout follows the
  // cursor). A new view has no result yet.
  void setView(ScenarioView* view, const QList<PlotPanel>& plots, plot::ZoomGroup* zoom);
  // A new run: the transport takes its times (keeping the cursor time when it can); true when
  // that moved the cursor, so the view is to be drawn there.
  bool setResult(std::shared_ptr<const RunResult> result);
  // Draws the view up to the cursor again (after a zoom: lines reduced for the visible range).
  void redraw();
  // The readout shows the replay time while playing or with the cursor before the end.
  void followCursor();
  // The time range every time plot shows (the following window); t1 <= t0: no change.
  void applyTimeWindow(double t0, double t1);
  // A replay key pressed in `target`: handled (true) or left to the widget (false).
  bool handleKey(QObject* target, QKeyEvent* event);
  // The replay state for a session: cursor time, show all, speed, window.
  QJsonValue saveState() const;
  void restoreState(const QJsonValue& v);

 private:
  void drawCursor(std::size_t index);

  TransportBar* transport_;
  QPointer<ConsistencyPanel> consistency_;
  QWidget* window_;
  QPointer<ScenarioView> view_;
  QList<PlotPanel> plots_;
  QPointer<plot::ZoomGroup> zoom_;
  std::shared_ptr<const RunResult> result_;
};

}  // namespace kfw
