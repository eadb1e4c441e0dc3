#include "plot_kit.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "draw_batch.h"
#include "plot_fast.h"
#include "plot_text.h"

namespace kfw::plot {

QColor color::cycle(int i) {
  static const QColor c[] = {kEstimate,
                             kSecond,
                             kThird,
                             kFourth,
                             kFifth,
                             QColor(140, 86, 75),
                             QColor(227, 119, 194),
                             QColor(23, 190, 207),
                             QColor(188, 189, 34),
                             QColor(127, 127, 127)};
  return c[static_cast<std::size_t>(i) % (sizeof c / sizeof c[0])];
}

QColor color::ghost(int i) {
  QColor c = cycle(5 + i % 5);  // brown, pink, cyan, olive, grey
  c.setAlpha(150);
  return c;
}

void removePlottables(std::initializer_list<QCPAbstractPlottable*> plottables) {
  for (QCPAbstractPlottable* p : plottables) {
    if (p) p->parentPlot()->removePlottable(p);
  }
}

void fitLegend(QCustomPlot* p, int width) {
  QCPLegend* l = p->legend;
  // Only the legend in makePlot's row (a view may have moved it beside the plot).
  if (!l || !l->visible() || l->layout() != p->plotLayout()) return;
  int widest = 1;
  for (int i = 0; i < l->itemCount(); ++i) {
    if (QCPAbstractLegendItem* item = l->item(i))  // null: an empty cell of the grid
      widest = std::max(widest, item->minimumOuterSizeHint().width());
  }
  const int room = std::max(1, width - 16);
  const int cols = std::max(1, room / (widest + l->columnSpacing()));
  if (l->wrap() != cols || l->fillOrder() != QCPLayoutGrid::foColumnsFirst) {
    l->setWrap(cols);
    l->setFillOrder(QCPLayoutGrid::foColumnsFirst, true);
  }
}

QCustomPlot* makePlot(QWidget* parent, const QString& title, const QString& xLabel,
                      const QString& yLabel) {
  auto* p = new QCustomPlot(parent);
  // An explicit minimum: QCustomPlot's own hint is its longest title or legend in one line, which
  // made the window wider than a 1280 px screen (titles wrap to the plot's width instead).
  p->setMinimumSize(200, 240);
  p->setNoAntialiasingOnDrag(true);
  // On screen, data are drawn without antialiasing (a slider drag redraws every plot; AA on tens
  // of thousands of points costs ~10x); exports switch it back on (setExportLook).
  p->setNotAntialiasedElements(QCP::aePlottables | QCP::aeFills);
  p->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
  QFont base = p->font();
  base.setPointSizeF(9.0);
  p->setFont(base);
  p->plotLayout()->insertRow(0);
  QFont tf = base;
  tf.setPointSizeF(10.5);
  tf.setBold(true);
  auto* te = new QCPTextElement(p, typeset(title), tf);
  te->setObjectName("title");
  p->plotLayout()->addElement(0, 0, te);
  p->xAxis->setLabel(typeset(xLabel));
  p->yAxis->setLabel(typeset(yLabel));
  // Every axis, shown or not: an unset font is QFont(), the application's, which presentation
  // scales (an axis made while presenting kept its large font after leaving).
  for (QCPAxis* a : {p->xAxis, p->yAxis, p->xAxis2, p->yAxis2}) {
    a->setLabelFont(base);
    a->setTickLabelFont(base);
  }
  p->legend->setVisible(true);
  QFont lf = base;
  lf.setPointSizeF(8.0);
  p->legend->setFont(lf);
  p->legend->setBrush(Qt::NoBrush);
  p->legend->setBorderPen(Qt::NoPen);
  p->legend->setRowSpacing(-4);
  p->legend->setColumnSpacing(10);
  p->legend->setMargins(QMargins(4, 0, 4, 0));
  // The legend leaves the axis rect for a row of its own under the title: it never hides data.
  p->axisRect()->insetLayout()->take(p->legend);
  p->axisRect()->insetLayout()->simplify();
  p->plotLayout()->insertRow(1);
  p->plotLayout()->addElement(1, 0, p->legend);
  p->plotLayout()->setRowStretchFactor(1, 0.001);
  p->plotLayout()->setRowSpacing(0);
  QObject::connect(p, &QCustomPlot::beforeReplot, p, [p] {
    fitLegend(p, p->width());
    keepUserHidden(p);
  });
  // A click on a legend entry hides its curve (a band: both edges), another shows it again.
  QObject::connect(p, &QCustomPlot::legendClick, p,
                   [p](QCPLegend*, QCPAbstractLegendItem* item, QMouseEvent*) {
                     auto* entry = qobject_cast<QCPPlottableLegendItem*>(item);
                     if (!entry) return;
                     QCPAbstractPlottable* c = entry->plottable();
                     setUserHidden(c, !userHidden(c));
                     p->replot();
                   });
  return p;
}

namespace {
const char* const kUserHidden = "kfwUserHidden";
const char* const kLegendInk = "kfwLegendInk";
}  // namespace

bool userHidden(const QCPAbstractPlottable* c) {
  return c->property(kUserHidden).toBool();
}

void setUserHidden(QCPAbstractPlottable* c, bool hidden) {
  QCustomPlot* p = c->parentPlot();
  c->setProperty(kUserHidden, hidden);
  if (!hidden) c->setVisible(true);
  if (auto* g = qobject_cast<QCPGraph*>(c)) {
    for (int i = 0; i < p->graphCount(); ++i) {
      QCPGraph* lower = p->graph(i);
      if (lower->channelFillGraph() != g) continue;
      lower->setProperty(kUserHidden, hidden);
      if (!hidden) lower->setVisible(true);
    }
  }
  // The entry greyed while its curve is hidden.
  if (QCPPlottableLegendItem* entry = p->legend ? p->legend->itemWithPlottable(c) : nullptr) {
    if (hidden) {
      entry->setProperty(kLegendInk, entry->textColor());
      entry->setTextColor(QColor(160, 160, 160));
    } else if (entry->property(kLegendInk).isValid()) {
      entry->setTextColor(entry->property(kLegendInk).value<QColor>());
    }
  }
  keepUserHidden(p);
}

void keepUserHidden(QCustomPlot* p) {
  // After the view's own setVisible (a new run shows its truth again): the user's choice stays.
  for (int i = 0; i < p->plottableCount(); ++i) {
    QCPAbstractPlottable* c = p->plottable(i);
    if (c->property(kUserHidden).toBool() && c->visible()) c->setVisible(false);
  }
}

namespace {

const char* const kDotsProperty = "kfwDots";

// A 2 × 2-pixel square dot. On screen it is blitted from a pixmap (≈ 0.1 µs a dot, a quarter of
// what a painted square costs at tens of thousands of dots); exports paint vector squares.
QCPScatterStyle dotStyle(const QColor& c, bool vector) {
  if (vector) return QCPScatterStyle(QCPScatterStyle::ssSquare, c, c, 1.5);
  QPixmap dot(2, 2);
  dot.fill(c);
  return QCPScatterStyle(dot);
}

}  // namespace

void setExportLook(QCustomPlot* p, bool exporting) {
  p->setNotAntialiasedElements(exporting ? QCP::aeNone : (QCP::aePlottables | QCP::aeFills));
  for (int i = 0; i < p->graphCount(); ++i) {
    QCPGraph* g = p->graph(i);
    // Only graphs still wearing the house dot (a caller may have given its own marker).
    const auto shape = g->scatterStyle().shape();
    const bool dot = shape == QCPScatterStyle::ssPixmap ||
                     (shape == QCPScatterStyle::ssSquare && g->scatterStyle().size() == 1.5);
    if (g->property(kDotsProperty).toBool() && dot)
      g->setScatterStyle(dotStyle(g->pen().color(), exporting));
  }
}

QCPGraph* addGraph(QCustomPlot* p, const QString& name, const QColor& c, Style s, double width) {
  QCPGraph* g = s == Style::kDots ? newDotGraph(p->xAxis, p->yAxis) : p->addGraph();
  g->setName(typeset(name));
  QPen pen(c);
  pen.setWidthF(width);
  switch (s) {
    case Style::kLine:
      break;
    case Style::kDashed:
      pen.setStyle(Qt::DashLine);
      break;
    case Style::kDots:
      g->setLineStyle(QCPGraph::lsNone);
      g->setProperty(kDotsProperty, true);
      g->setScatterStyle(dotStyle(c, false));
      break;
    case Style::kStep:
      g->setLineStyle(QCPGraph::lsStepLeft);
      break;
  }
  g->setPen(pen);
  return g;
}

QCPGraph* addGhost(QCustomPlot* p, const QString& name, int i, Style s) {
  QCPGraph* g = addGraph(p, name, color::ghost(i), s, 2.0);
  QPen pen = g->pen();
  pen.setDashPattern({4.0, 2.0});
  g->setPen(pen);
  g->setProperty("kfwGhost", true);
  return g;
}

QCPGraph* addGraphRight(QCustomPlot* p, const QString& name, const QColor& c,
                        const QString& rightLabel) {
  QCPGraph* g = p->addGraph(p->xAxis, p->yAxis2);
  g->setName(typeset(name));
  QPen pen(c);
  pen.setWidthF(1.0);
  g->setPen(pen);
  p->yAxis2->setVisible(true);
  p->yAxis2->setLabel(typeset(rightLabel));
  return g;
}

void setLog(QCPAxis* axis) {
  axis->setScaleType(QCPAxis::stLogarithmic);
  QSharedPointer<QCPAxisTickerLog> t(new QCPAxisTickerLog);
  t->setLogBase(10);
  t->setSubTickCount(8);
  axis->setTicker(t);
  axis->setNumberFormat("gb");
  axis->setNumberPrecision(3);
}

namespace {
// c at `alpha` over white, as an opaque colour.
QColor overWhite(const QColor& c, int alpha) {
  auto mix = [alpha](int v) { return (v * alpha + 255 * (255 - alpha) + 127) / 255; };
  return QColor(mix(c.red()), mix(c.green()), mix(c.blue()));
}
}  // namespace

namespace {
// A band's upper edge, whose legend icon is the band's fill with its edge (a line icon would not
// tell one translucent band from another).
class BandEdge final : public QCPGraph {
 public:
  BandEdge(QCPAxis* key, QCPAxis* value, const QColor& fill) : QCPGraph(key, value), fill_(fill) {}

 protected:
  void drawLegendIcon(QCPPainter* painter, const QRectF& rect) const override {
    QColor f = fill_;
    f.setAlpha(std::max(f.alpha(), 120));
    const QRectF r = rect.adjusted(1.0, 2.0, -1.0, -2.0);
    if (!property("kfwOutlined").toBool()) {
      painter->setPen(QPen(pen().color().darker(130)));
      painter->setBrush(f);
      painter->drawRect(r);
      return;
    }
    // An outlined band (outlineBand): the fill between its two edge lines, as in the plot.
    painter->setPen(Qt::NoPen);
    painter->setBrush(f);
    painter->drawRect(r);
    QPen edge = pen();
    edge.setWidthF(std::min(edge.widthF(), 2.0));
    painter->setPen(edge);
    painter->drawLine(r.topLeft(), r.topRight());
    painter->drawLine(r.bottomLeft(), r.bottomRight());
  }

 private:
  QColor fill_;
};
}  // namespace

Band addBand(QCustomPlot* p, const QString& name, const QColor& c, bool overlaps) {
  // A translucent fill costs several milliseconds a replot on a dense band (alpha blending over
  // the whole area); a band that stands alone is drawn in the same colour made opaque.
  const QColor fill = overlaps ? QColor(c.red(), c.green(), c.blue(), 50) : overWhite(c, 50);
  const QColor edge = overlaps ? QColor(c.red(), c.green(), c.blue(), 90) : overWhite(c, 90);
  Band b;
  b.upper = new BandEdge(p->xAxis, p->yAxis, fill);
  b.upper->setName(typeset(name));
  b.upper->addToLegend();
  b.upper->setPen(QPen(edge));
  b.upper->setBrush(Qt::NoBrush);
  b.lower = newBandFill(p->xAxis, p->yAxis);
  b.lower->setPen(QPen(edge));
  b.lower->setBrush(QBrush(fill));
  b.lower->setChannelFillGraph(b.upper);
  b.lower->setName("");  // the band is named by its upper edge
  b.lower->removeFromLegend();
  return b;
}

void outlineBand(const Band& b, Qt::PenStyle style, double width) {
  QColor c = b.upper->pen().color();
  c.setAlpha(255);
  QPen edge(c, width, style);
  edge.setCapStyle(Qt::FlatCap);
  b.upper->setPen(edge);
  b.lower->setPen(edge);
  b.upper->setProperty("kfwOutlined", true);
  // A paler fill: where fills overlap the blend stays faint, the edges carry the distinction.
  QColor fill = b.lower->brush().color();
  fill.setAlpha(std::min(fill.alpha(), 30));
  b.lower->setBrush(fill);
}

QCPItemStraightLine* addCursor(QCustomPlot* p) {
  auto* line = new QCPItemStraightLine(p);
  QPen pen(QColor(200, 0, 0, 160));
  pen.setWidthF(1.0);
  line->setPen(pen);
  line->point1->setTypeX(QCPItemPosition::ptPlotCoords);
  line->point1->setTypeY(QCPItemPosition::ptAxisRectRatio);
  line->point2->setTypeX(QCPItemPosition::ptPlotCoords);
  line->point2->setTypeY(QCPItemPosition::ptAxisRectRatio);
  line->point1->setCoords(0, 0);
  line->point2->setCoords(0, 1);
  line->setVisible(false);
  line->setSelectable(false);
  return line;
}

void setCursorAt(QCPItemStraightLine* line, double x, bool visible) {
  line->point1->setCoords(x, 0);
  line->point2->setCoords(x, 1);
  line->setVisible(visible);
}

QCPItemStraightLine* addHLine(QCustomPlot* p, double y, const QColor& c, Qt::PenStyle s) {
  auto* line = new QCPItemStraightLine(p);
  QPen pen(c);
  pen.setStyle(s);
  line->setPen(pen);
  line->point1->setTypeX(QCPItemPosition::ptAxisRectRatio);
  line->point2->setTypeX(QCPItemPosition::ptAxisRectRatio);
  setHLine(line, y);
  line->setSelectable(false);
  return line;
}

void setHLine(QCPItemStraightLine* line, double y) {
  line->point1->setCoords(0, y);
  line->point2->setCoords(1, y);
}

namespace {
// The value range of the visible plottables on `axis` over keys in [k0, k1]; invalid if none.
QCPRange valueRangeIn(QCustomPlot* p, QCPAxis* axis, double k0, double k1, bool& found) {
  settleDraws(p);
  found = false;
  QCPRange all;
  const auto sign = axis->scaleType() == QCPAxis::stLogarithmic ? QCP::sdPositive : QCP::sdBoth;
  for (int i = 0; i < p->plottableCount(); ++i) {
    QCPAbstractPlottable* pl = p->plottable(i);
    if (!pl->visible() || pl->valueAxis() != axis) continue;
    bool f = false;
    const QCPRange r = pl->getValueRange(f, sign, QCPRange(k0, k1));
    if (!f) continue;
    if (found) {
      all.expand(r);
    } else {
      all = r;
      found = true;
    }
  }
  return all;
}
}  // namespace

namespace {
const char* const kZoomX = "kfwZoomX";
const char* const kZoomY = "kfwZoomY";
const char* const kTime = "kfwTime";
}  // namespace

bool userZoomedX(const QCustomPlot* p) {
  return p && p->property(kZoomX).toBool();
}
bool userZoomedY(const QCustomPlot* p) {
  return p && p->property(kZoomY).toBool();
}
void setUserZoom(QCustomPlot* p, bool x, bool y) {
  p->setProperty(kZoomX, x);
  p->setProperty(kZoomY, y);
}
int axisRectRow(QCustomPlot* p) {
  QCPLayoutGrid* layout = p->plotLayout();
  for (int row = 0; row < layout->rowCount(); ++row) {
    if (layout->element(row, 0) == p->axisRect()) return row;
  }
  return layout->rowCount() - 1;
}

bool isTimePlot(const QCustomPlot* p) {
  return p && p->property(kTime).toBool();
}

namespace {
// Fits each value axis to the visible plottables' values over keys [k0, k1], with the house
// margins (6 % below, 12 % above; ×1.5 each way on a log axis). Axes with no data there keep
// their range.
void fitValues(QCustomPlot* p, double k0, double k1) {
  for (QCPAxis* a : {p->yAxis, p->yAxis2}) {
    if (!a->visible() && a == p->yAxis2) continue;
    bool found = false;
    QCPRange r = valueRangeIn(p, a, k0, k1, found);
    if (!found) continue;
    if (a->scaleType() == QCPAxis::stLogarithmic) {
      if (r.lower > 0 && r.upper > 0) a->setRange(r.lower / 1.5, r.upper * 1.5);
    } else {
      const double span = r.size() > 0 ? r.size() : std::max(1.0, std::abs(r.center()));
      a->setRange(r.lower - 0.06 * span, r.upper + 0.12 * span);
    }
  }
}
}  // namespace

void rescale(QCustomPlot* p, double x0, double x1, double settle) {
  settleDraws(p);
  if (x1 > x0) p->setProperty(kTime, true);
  const bool keep_x = userZoomedX(p), keep_y = userZoomedY(p);
  if (keep_x && keep_y) return;
  const QCPRange xr = p->xAxis->range(), yr = p->yAxis->range(), y2r = p->yAxis2->range();
  rescaleAuto(p, x0, x1, settle);
  if (keep_x) {
    // Zoomed in time: the value axes fit what is in view, not the whole run.
    p->xAxis->setRange(xr);
    if (!keep_y) fitValues(p, xr.lower, xr.upper);
  }
  if (keep_y) {
    p->yAxis->setRange(yr);
    p->yAxis2->setRange(y2r);
  }
}

void rescaleAuto(QCustomPlot* p, double x0, double x1, double settle) {
  settleDraws(p);
  p->rescaleAxes(true);
  if (x1 > x0 && settle > x0) {
    for (QCPAxis* a : {p->yAxis, p->yAxis2}) {
      bool found = false;
      const QCPRange r = valueRangeIn(p, a, settle, x1, found);
      if (!found) continue;
      const bool log = a->scaleType() == QCPAxis::stLogarithmic;
      if (r.lower < r.upper) {
        a->setRange(r);
      } else {
        a->setRange(log ? QCPRange(r.lower / 2, r.upper * 2) : QCPRange(r.lower - 1, r.upper + 1));
      }
    }
  }
  for (QCPAxis* a : {p->yAxis, p->yAxis2}) {
    if (!a->visible() && a == p->yAxis2) continue;
    QCPRange r = a->range();
    if (a->scaleType() == QCPAxis::stLogarithmic) {
      if (r.lower > 0 && r.upper > 0) a->setRange(r.lower / 1.5, r.upper * 1.5);
    } else {
      const double span = r.size() > 0 ? r.size() : std::max(1.0, std::abs(r.center()));
      a->setRange(r.lower - 0.06 * span, r.upper + 0.12 * span);
    }
  }
  if (x1 > x0) p->xAxis->setRange(x0, x1);
}

void replot(QCustomPlot* p) {
  requestReplot(p);
}

}  // namespace kfw::plot
