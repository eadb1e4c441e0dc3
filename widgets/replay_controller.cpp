#include "replay_controller.h"

#include <qcustomplot.h>

#include <QAbstractSpinBox>
#include <QApplication>
#include <QJsonObject>
#include <QKeyEvent>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QTextEdit>
#include <limits>

#include "consistency_panel.h"
#include "draw_batch.h"
#include "plot_kit.h"
#include "plot_readout.h"
#include "plot_zoom.h"
#include "transport_bar.h"

namespace kfw {

namespace {

// Space, ←, →, Home and End for the replay, seen before the focused widget sees them.
class ReplayKeys : public QObject {
 public:
  explicit ReplayKeys(ReplayController* replay) : QObject(replay), replay_(replay) {}
  bool eventFilter(QObject* target, QEvent* event) override {
    if (event->type() == QEvent::KeyPress || event->type() == QEvent::ShortcutOverride) {
      auto* key = static_cast<QKeyEvent*>(event);
      if (replay_->handleKey(target, key)) {
        // ShortcutOverride accepted: the key comes back as a KeyPress, handled there.
        if (event->type() == QEvent::ShortcutOverride) return false;
        return true;
      }
    }
    return QObject::eventFilter(target, event);
  }

 private:
  ReplayController* replay_;
};

// Where a typed key is text: line edits (not a spin box's own), text editors.
bool isTextEntry(const QWidget* w) {
  if (!w) return false;
  if (qobject_cast<const QTextEdit*>(w) || qobject_cast<const QPlainTextEdit*>(w)) return true;
  if (auto* e = qobject_cast<const QLineEdit*>(w)) {
    return !qobject_cast<const QAbstractSpinBox*>(e->parentWidget());
  }
  return false;
}

}  // namespace

ReplayController::ReplayController(TransportBar* transport, ConsistencyPanel* consistency,
                                   QWidget* window)
    : QObject(window), transport_(transport), consistency_(consistency), window_(window) {
  qApp->installEventFilter(new ReplayKeys(this));
  connect(transport_, &TransportBar::cursorChanged, this, &ReplayController::drawCursor);
  connect(transport_, &TransportBar::timeWindowChanged, this, &ReplayController::applyTimeWindow);
  connect(transport_, &TransportBar::cursorChanged, this, &ReplayController::followCursor);
  connect(transport_, &TransportBar::playingChanged, this, &ReplayController::followCursor);
}

void ReplayController::setView(ScenarioView* view, const QList<PlotPanel>& plots,
                               plot::ZoomGroup* zoom) {
  view_ = view;
  plots_ = plots;
  zoom_ = zoom;
  result_.reset();
}

bool ReplayController::setResult(std::shared_ptr<const RunResult> result) {
  result_ = std::move(result);
  const std::size_t before = transport_->cursor();
  transport_->setTimes(result_->t);
  return transport_->cursor() != before;
}

void ReplayController::drawCursor(std::size_t index) {
  plot::DrawBatch batch;  // a replay frame: reductions on both cores
  if (view_) view_->setCursor(index);
}

void ReplayController::redraw() {
  plot::DrawBatch batch;
  if (view_ && result_) view_->setCursor(transport_->cursor());
}

void ReplayController::followCursor() {
  if (!zoom_ || !zoom_->readout()) return;
  const std::size_t i = transport_->cursor();
  const bool shown =
      result_ && i < result_->t.size() && (transport_->playing() || i + 1 < result_->t.size());
  // Playing: the cursor line only (a box on every plot covered the data); paused: the values.
  zoom_->readout()->setReplayTime(shown ? result_->t[i] : std::numeric_limits<double>::quiet_NaN(),
                                  !transport_->playing());
}

void ReplayController::applyTimeWindow(double t0, double t1) {
  if (!(t1 > t0)) return;
  // As a zoom of the linked time axes, so the next redraw keeps (and reduces data for) it.
  if (zoom_) zoom_->followTime(t0, t1);
  QList<PlotPanel> all = plots_;
  if (consistency_) all << consistency_->plots();
  for (const auto& p : all) {
    if (!plot::isTimePlot(p.plot)) continue;
    p.plot->xAxis->setRange(t0, t1);
    plot::replotQueued(p.plot);
  }
}

bool ReplayController::handleKey(QObject* target, QKeyEvent* event) {
  auto* w = qobject_cast<QWidget*>(target);
  if (!w || w->window() != window_) return false;
  const Qt::KeyboardModifiers mods = event->modifiers() & ~Qt::KeypadModifier;
  if (mods != Qt::NoModifier) return false;
  const int k = event->key();
  if (k != Qt::Key_Space && k != Qt::Key_Left && k != Qt::Key_Right && k != Qt::Key_Home &&
      k != Qt::Key_End) {
    return false;
  }
  QWidget* focus = QApplication::focusWidget();
  if (isTextEntry(focus) || isTextEntry(w)) return false;
  // Home and End on a plot are the plot's (reset the zoom).
  if ((k == Qt::Key_Home || k == Qt::Key_End) &&
      (qobject_cast<QCustomPlot*>(focus) || qobject_cast<QCustomPlot*>(w))) {
    return false;
  }
  if (event->type() == QEvent::ShortcutOverride) {
    event->accept();
    return true;
  }
  switch (k) {
    case Qt::Key_Space:
      if (!event->isAutoRepeat()) transport_->togglePlay();
      break;
    case Qt::Key_Left:
      transport_->stepBy(-1);
      break;
    case Qt::Key_Right:
      transport_->stepBy(1);
      break;
    case Qt::Key_Home:
      transport_->seek(0);
      break;
    case Qt::Key_End:
      transport_->seek(static_cast<std::size_t>(-1));
      break;
    default:
      return false;
  }
  return true;
}

QJsonValue ReplayController::saveState() const {
  return QJsonValue(transport_->saveState());
}

void ReplayController::restoreState(const QJsonValue& v) {
  transport_->restoreState(v.toObject());
  if (view_) view_->setCursor(transport_->cursor());
}

}  // namespace kfw
