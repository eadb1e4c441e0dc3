#include "plot_zoom.h"

#include <qcustomplot.h>

#include <QJsonArray>
#include <QJsonObject>
#include <QKeyEvent>
#include <QTimer>
#include <QWheelEvent>

#include "draw_batch.h"
#include "plot_kit.h"
#include "plot_readout.h"

namespace kfw::plot {

namespace {

const char* const kAutoX = "kfwAutoX";  // the range an axis had before the user's first change
const char* const kAutoY = "kfwAutoY";
const char* const kAutoY2 = "kfwAutoY2";

QJsonArray rangeJson(const QCPRange& r) {
  return QJsonArray{r.lower, r.upper};
}

bool rangeFrom(const QJsonValue& v, QCPRange& r) {
  const QJsonArray a = v.toArray();
  if (a.size() != 2 || !a[0].isDouble() || !a[1].isDouble()) return false;
  r = QCPRange(a[0].toDouble(), a[1].toDouble());
  return r.lower < r.upper && std::isfinite(r.lower) && std::isfinite(r.upper);
}

QVariant rangeVariant(const QCPRange& r) {
  return QVariant::fromValue(QPointF(r.lower, r.upper));
}

void restoreAuto(QCPAxis* a, const char* key) {
  const QVariant v = a->parentPlot()->property(key);
  if (!v.isValid()) return;
  const QPointF r = v.toPointF();
  a->setRange(r.x(), r.y());
  a->parentPlot()->setProperty(key, QVariant());
}

}  // namespace

ZoomGroup::ZoomGroup(const QList<PlotPanel>& plots, std::function<void()> redraw, QObject* parent)
    : QObject(parent), plots_(plots), redraw_(std::move(redraw)) {
  redraw_timer_ = new QTimer(this);
  redraw_timer_->setSingleShot(true);
  redraw_timer_->setInterval(40);
  connect(redraw_timer_, &QTimer::timeout, this, [this] {
    if (redraw_) redraw_();
  });
  for (const PlotPanel& panel : plots_) {
    QCustomPlot* p = panel.plot;
    if (!p) continue;
    p->installEventFilter(this);
    p->setMouseTracking(true);
    p->setFocusPolicy(Qt::ClickFocus);
    p->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
    p->axisRect()->setRangeDragAxes({p->xAxis}, {p->yAxis, p->yAxis2});
    p->axisRect()->setRangeZoomAxes({p->xAxis}, {p->yAxis, p->yAxis2});
    p->selectionRect()->setPen(QPen(QColor(60, 60, 60), 1, Qt::DashLine));
    p->selectionRect()->setBrush(QColor(60, 120, 200, 40));
    auto watch = [this, p](QCPAxis* axis, const char* key, bool x) {
      connect(axis, qOverload<const QCPRange&, const QCPRange&>(&QCPAxis::rangeChanged), this,
              [this, p, key, x](const QCPRange&, const QCPRange& old) {
                if (interacting_ != p || linking_) return;
                if (!p->property(key).isValid()) p->setProperty(key, rangeVariant(old));
                userChanged(p, x, !x);
              });
    };
    watch(p->xAxis, kAutoX, true);
    watch(p->yAxis, kAutoY, false);
    watch(p->yAxis2, kAutoY2, false);
  }
  readout_ = new PlotReadout(plots_, this);
}

ZoomGroup::~ZoomGroup() = default;

void ZoomGroup::userChanged(QCustomPlot* source, bool x, bool y) {
  setUserZoom(source, userZoomedX(source) || x, userZoomedY(source) || y);
  if (x && isTimePlot(source)) {
    const QCPRange r = source->xAxis->range();
    linking_ = true;
    for (const PlotPanel& panel : plots_) {
      QCustomPlot* q = panel.plot;
      if (q == source || !isTimePlot(q)) continue;
      if (!q->property(kAutoX).isValid()) q->setProperty(kAutoX, rangeVariant(q->xAxis->range()));
      q->xAxis->setRange(r);
      setUserZoom(q, true, userZoomedY(q));
      plot::replotQueued(q);
    }
    linking_ = false;
  }
  scheduleRedraw();
}

void ZoomGroup::scheduleRedraw() {
  redraw_timer_->start();
}

void ZoomGroup::zoomTime(double t0, double t1) {
  followTime(t0, t1);
  if (redraw_) redraw_();
}

void ZoomGroup::followTime(double t0, double t1) {
  linking_ = true;
  for (const PlotPanel& panel : plots_) {
    QCustomPlot* q = panel.plot;
    if (!isTimePlot(q)) continue;
    if (!q->property(kAutoX).isValid()) q->setProperty(kAutoX, rangeVariant(q->xAxis->range()));
    q->xAxis->setRange(t0, t1);
    setUserZoom(q, true, userZoomedY(q));
  }
  linking_ = false;
}

void ZoomGroup::resetAll() {
  redraw_timer_->stop();
  linking_ = true;
  for (const PlotPanel& panel : plots_) {
    QCustomPlot* p = panel.plot;
    setUserZoom(p, false, false);
    restoreAuto(p->xAxis, kAutoX);
    restoreAuto(p->yAxis, kAutoY);
    restoreAuto(p->yAxis2, kAutoY2);
  }
  linking_ = false;
  if (redraw_) redraw_();
  for (const PlotPanel& panel : plots_)
    plot::replotQueued(panel.plot);
}

QJsonValue ZoomGroup::save() const {
  QJsonObject o;
  for (const PlotPanel& panel : plots_) {
    QCustomPlot* p = panel.plot;
    if (!userZoomedX(p) && !userZoomedY(p)) continue;
    QJsonObject e;
    if (userZoomedX(p)) e["x"] = rangeJson(p->xAxis->range());
    if (userZoomedY(p)) {
      e["y"] = rangeJson(p->yAxis->range());
      if (p->yAxis2->visible()) e["y2"] = rangeJson(p->yAxis2->range());
    }
    o[panel.name] = e;
  }
  return o;
}

void ZoomGroup::restore(const QJsonValue& v) {
  const QJsonObject o = v.toObject();
  linking_ = true;
  for (const PlotPanel& panel : plots_) {
    if (!o.contains(panel.name)) continue;
    QCustomPlot* p = panel.plot;
    const QJsonObject e = o[panel.name].toObject();
    QCPRange r;
    bool zx = false, zy = false;
    if (rangeFrom(e["x"], r)) {
      p->setProperty(kAutoX, rangeVariant(p->xAxis->range()));
      p->xAxis->setRange(r);
      zx = true;
    }
    if (rangeFrom(e["y"], r)) {
      p->setProperty(kAutoY, rangeVariant(p->yAxis->range()));
      p->yAxis->setRange(r);
      zy = true;
    }
    if (rangeFrom(e["y2"], r)) {
      p->setProperty(kAutoY2, rangeVariant(p->yAxis2->range()));
      p->yAxis2->setRange(r);
    }
    setUserZoom(p, zx, zy);
  }
  linking_ = false;
  if (redraw_) redraw_();
}

bool ZoomGroup::eventFilter(QObject* watched, QEvent* event) {
  auto* p = qobject_cast<QCustomPlot*>(watched);
  if (!p) return false;
  auto endGesture = [this] { QTimer::singleShot(0, this, [this] { interacting_ = nullptr; }); };
  switch (event->type()) {
    case QEvent::Wheel: {
      // Over an axis: that axis only; over the data: both.
      const QPointF pos = static_cast<QWheelEvent*>(event)->position();
      const QRect r = p->axisRect()->rect();
      Qt::Orientations o = Qt::Horizontal | Qt::Vertical;
      if (pos.y() > r.bottom() && pos.x() >= r.left() && pos.x() <= r.right()) {
        o = Qt::Horizontal;
      } else if ((pos.x() < r.left() || pos.x() > r.right()) && pos.y() >= r.top() &&
                 pos.y() <= r.bottom()) {
        o = Qt::Vertical;
      }
      p->axisRect()->setRangeZoom(o);
      interacting_ = p;
      endGesture();
      return false;
    }
    case QEvent::MouseButtonPress: {
      auto* me = static_cast<QMouseEvent*>(event);
      const bool box =
          me->button() == Qt::RightButton || (me->modifiers() & Qt::ControlModifier) != 0;
      p->setSelectionRectMode(box ? QCP::srmZoom : QCP::srmNone);
      interacting_ = p;
      return false;
    }
    case QEvent::MouseButtonRelease:
      endGesture();
      return false;
    case QEvent::MouseButtonDblClick:
      resetAll();
      return true;
    case QEvent::ShortcutOverride:
    case QEvent::KeyPress: {
      auto* ke = static_cast<QKeyEvent*>(event);
      if (ke->key() != Qt::Key_Home) return false;
      event->accept();
      if (event->type() == QEvent::KeyPress) resetAll();
      return true;
    }
    case QEvent::MouseMove:
      readout_->mouseMoved(p, static_cast<QMouseEvent*>(event)->position());
      return false;
    case QEvent::Leave:
      readout_->hide();
      return false;
    default:
      return false;
  }
}

}  // namespace kfw::plot
