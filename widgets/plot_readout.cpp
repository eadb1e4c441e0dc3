#include "plot_readout.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "plot_kit.h"

namespace kfw::plot {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

QString number(double v) {
  if (!std::isfinite(v)) return "—";
  return QString::number(v, 'g', 5);
}

// The band whose upper edge is `upper` (the graph filled to it), if any.
const QCPGraph* bandLower(const QCustomPlot* p, const QCPGraph* upper) {
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->channelFillGraph() == upper) return p->graph(i);
  }
  return nullptr;
}

// Linear interpolation in a graph's own points (a curve over a parameter).
double interpolate(const QCPGraph* g, double x) {
  const auto d = g->data();
  if (d->isEmpty()) return kNaN;
  auto it = std::lower_bound(d->constBegin(), d->constEnd(), x,
                             [](const QCPGraphData& a, double k) { return a.key < k; });
  if (it == d->constEnd() || it == d->constBegin()) {
    if (it != d->constEnd() && it->key == x) return it->value;
    return kNaN;
  }
  const auto prev = it - 1;
  const bool log = g->keyAxis()->scaleType() == QCPAxis::stLogarithmic && prev->key > 0;
  const double f = log ? std::log(x / prev->key) / std::log(it->key / prev->key)
                       : (x - prev->key) / (it->key - prev->key);
  return prev->value + f * (it->value - prev->value);
}

}  // namespace

double valueAt(const QCPGraph* g, double t) {
  const SeriesSource s = seriesSource(g);
  if (s.x && s.y) {
    const std::size_t n = std::min({s.n, s.x->size(), s.y->size()});
    const auto end = s.x->begin() + static_cast<std::ptrdiff_t>(n);
    const auto it = std::upper_bound(s.x->begin(), end, t);
    if (it == s.x->begin()) return kNaN;
    return (*s.y)[static_cast<std::size_t>(it - s.x->begin()) - 1];
  }
  const auto d = g->data();
  auto it = std::upper_bound(d->constBegin(), d->constEnd(), t,
                             [](double k, const QCPGraphData& a) { return k < a.key; });
  if (it == d->constBegin()) return kNaN;
  return (it - 1)->value;
}

QList<QPair<QString, double>> curveValuesAt(const QCustomPlot* p, double t) {
  QList<QPair<QString, double>> out;
  for (int i = 0; i < p->graphCount(); ++i) {
    const QCPGraph* g = p->graph(i);
    if (!g->visible() || g->name().isEmpty() || g->data()->isEmpty()) continue;
    if (const QCPGraph* lower = bandLower(p, g)) {
      // The run's limits at the sample, not the drawn envelope of a column (issue 32, item 2).
      double lo = kNaN, hi = kNaN;
      if (!bandLimitsAt(g, t, lo, hi)) {
        lo = valueAt(lower, t);
        hi = valueAt(g, t);
      }
      out.append({g->name() + " (low)", lo});
      out.append({g->name() + " (high)", hi});
      continue;
    }
    out.append({g->name(), valueAt(g, t)});
  }
  return out;
}

PlotReadout::PlotReadout(const QList<PlotPanel>& plots, QObject* parent)
    : QObject(parent), replay_t_(kNaN) {
  for (const PlotPanel& panel : plots) {
    QCustomPlot* p = panel.plot;
    if (!p) continue;
    Marks m;
    m.plot = p;
    // QCustomPlot's topmost layer, buffered already (the box zoom's rectangle): a layer of its
    // own would split the plot's other layers into more paint buffers, each cleared on every
    // replot and drawn on every repaint.
    m.layer = p->layer("overlay");
    m.layer->setMode(QCPLayer::lmBuffered);
    const QString previous = p->currentLayer()->name();
    p->setCurrentLayer(m.layer);
    m.line = new QCPItemStraightLine(p);
    m.line->setPen(QPen(QColor(40, 40, 40, 170), 1.0, Qt::DotLine));
    m.line->point1->setTypeY(QCPItemPosition::ptAxisRectRatio);
    m.line->point2->setTypeY(QCPItemPosition::ptAxisRectRatio);
    m.line->setSelectable(false);
    m.line->setVisible(false);
    m.label = new QCPItemText(p);
    m.label->position->setType(QCPItemPosition::ptAbsolute);
    m.label->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
    m.label->setTextAlignment(Qt::AlignLeft);
    m.label->setFont(QFont(p->font().family(), 8));
    m.label->setPadding(QMargins(4, 2, 4, 2));
    m.label->setBrush(QColor(255, 255, 240, 235));
    m.label->setPen(QPen(QColor(160, 160, 160)));
    m.label->setClipToAxisRect(false);
    m.label->setSelectable(false);
    m.label->setVisible(false);
    p->setCurrentLayer(previous);
    marks_.push_back(m);
  }
}

PlotReadout::Marks* PlotReadout::find(const QCustomPlot* p) {
  for (Marks& m : marks_) {
    if (m.plot == p) return &m;
  }
  return nullptr;
}

void PlotReadout::place(Marks& m, const QString& text, double x_px) {
  m.label->setText(text);
  m.label->setVisible(!text.isEmpty());
  if (text.isEmpty()) return;
  // Right of the cursor, or left of it near the right edge; never past the axis rect's edges
  // (it was cut at the plot's edges).
  const QRect r = m.plot->axisRect()->rect();
  const QMargins pad = m.label->padding();
  const QSizeF box = QFontMetricsF(m.label->font())
                         .boundingRect(QRectF(0, 0, 1e6, 1e6), Qt::AlignLeft, text)
                         .size() +
                     QSizeF(pad.left() + pad.right() + 2, pad.top() + pad.bottom() + 2);
  const bool left = x_px + 8 + box.width() > r.right();
  double x = left ? x_px - 8 - box.width() : x_px + 8;
  x = std::clamp(x, double(r.left()), std::max(double(r.left()), r.right() - box.width()));
  m.label->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
  m.label->position->setCoords(x, r.top() + 4);
}

void PlotReadout::showTime(double t, QCustomPlot* hovered) {
  drawTime(t, hovered, false);
}

void PlotReadout::drawTime(double t, const QCustomPlot* hovered, bool label_all) {
  for (Marks& m : marks_) {
    if (!isTimePlot(m.plot)) {
      if (m.line->visible() || m.label->visible()) {
        m.line->setVisible(false);
        m.label->setVisible(false);
        m.layer->replot();
      }
      continue;
    }
    m.line->point1->setCoords(t, 0);
    m.line->point2->setCoords(t, 1);
    m.line->setVisible(true);
    if (label_all || m.plot == hovered) {
      place(m, timeText(m.plot, t), m.plot->xAxis->coordToPixel(t));
    } else {
      m.label->setVisible(false);
    }
    m.layer->replot();
  }
}

void PlotReadout::showPoint(QCustomPlot* p, const QPointF& pos) {
  Marks* m = find(p);
  if (!m) return;
  const double x = p->xAxis->pixelToCoord(pos.x()), y = p->yAxis->pixelToCoord(pos.y());
  QString text;
  for (int i = 0; i < p->plottableCount(); ++i) {
    auto* map = qobject_cast<QCPColorMap*>(p->plottable(i));
    if (!map) continue;
    int a = 0, b = 0;
    map->data()->coordToCell(x, y, &a, &b);
    if (a < 0 || b < 0 || a >= map->data()->keySize() || b >= map->data()->valueSize()) continue;
    const QString scale = map->colorScale() ? map->colorScale()->axis()->label() : "value";
    text = QString("%1 = %2\n%3 = %4\n%5 = %6")
               .arg(p->xAxis->label(), number(x), p->yAxis->label(), number(y), scale,
                    number(map->data()->cell(a, b)));
  }
  if (text.isEmpty() && p->graphCount() > 0) {
    text = QString("%1 = %2").arg(p->xAxis->label(), number(x));
    for (int i = 0; i < p->graphCount(); ++i) {
      const QCPGraph* g = p->graph(i);
      if (!g->visible() || g->name().isEmpty() || g->data()->size() < 2) continue;
      text += QString("\n%1: %2").arg(g->name(), number(interpolate(g, x)));
    }
    m->line->point1->setCoords(x, 0);
    m->line->point2->setCoords(x, 1);
    m->line->setVisible(true);
  }
  place(*m, text, pos.x());
  m->layer->replot();
}

QString PlotReadout::timeText(const QCustomPlot* p, double t) const {
  QString text = QString("t = %1 s").arg(number(t));
  for (const auto& [name, v] : curveValuesAt(p, t))
    text += QString("\n%1: %2").arg(name, number(v));
  return text;
}

void PlotReadout::showReplay() {
  // Every time plot: the line and its values at the replay time (nobody hovers one to choose).
  drawTime(replay_t_, nullptr, replay_labels_);
}

void PlotReadout::setReplayTime(double t, bool labels) {
  replay_t_ = t;
  replay_labels_ = labels;
  if (hovering_) return;  // the mouse's readout stays; the replay's comes back when it leaves
  if (std::isfinite(t)) {
    showReplay();
  } else {
    hideAll();
  }
}

void PlotReadout::mouseMoved(QCustomPlot* p, const QPointF& pos) {
  if (!p->axisRect()->rect().contains(pos.toPoint())) {
    hide();
    return;
  }
  if (!hovering_) {
    hovering_ = true;
    hideAll();  // the replay's labels on the other plots
  }
  if (isTimePlot(p)) {
    showTime(p->xAxis->pixelToCoord(pos.x()), p);
  } else {
    for (Marks& m : marks_) {
      if (m.plot != p && (m.line->visible() || m.label->visible())) {
        m.line->setVisible(false);
        m.label->setVisible(false);
        m.layer->replot();
      }
    }
    showPoint(p, pos);
  }
}

void PlotReadout::hide() {
  hovering_ = false;
  if (std::isfinite(replay_t_)) {
    showReplay();
  } else {
    hideAll();
  }
}

void PlotReadout::hideAll() {
  for (Marks& m : marks_) {
    if (!m.line->visible() && !m.label->visible()) continue;
    m.line->setVisible(false);
    m.label->setVisible(false);
    m.layer->replot();
  }
}

QString PlotReadout::text(const QCustomPlot* p) const {
  for (const Marks& m : marks_) {
    if (m.plot == p) return m.label->visible() ? m.label->text() : QString();
  }
  return {};
}

double PlotReadout::lineAt(const QCustomPlot* p) const {
  for (const Marks& m : marks_) {
    if (m.plot == p) return m.line->visible() ? m.line->point1->coords().x() : kNaN;
  }
  return kNaN;
}

}  // namespace kfw::plot
