#include "plot_kit.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>

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

QCustomPlot* makePlot(QWidget* parent, const QString& title, const QString& xLabel,
                      const QString& yLabel) {
  auto* p = new QCustomPlot(parent);
  p->setMinimumHeight(240);
  p->setNoAntialiasingOnDrag(true);
  // On screen, data are drawn without antialiasing (a slider drag redraws every plot; AA on tens
  // of thousands of points costs ~10x); exports switch it back on (plot_export.cpp).
  p->setNotAntialiasedElements(QCP::aePlottables | QCP::aeFills);
  p->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
  QFont base = p->font();
  base.setPointSizeF(9.0);
  p->setFont(base);
  p->plotLayout()->insertRow(0);
  QFont tf = base;
  tf.setPointSizeF(10.5);
  tf.setBold(true);
  auto* te = new QCPTextElement(p, title, tf);
  te->setObjectName("title");
  p->plotLayout()->addElement(0, 0, te);
  p->xAxis->setLabel(xLabel);
  p->yAxis->setLabel(yLabel);
  for (QCPAxis* a : {p->xAxis, p->yAxis, p->yAxis2}) {
    a->setLabelFont(base);
    a->setTickLabelFont(base);
  }
  p->legend->setVisible(true);
  QFont lf = base;
  lf.setPointSizeF(8.0);
  p->legend->setFont(lf);
  p->legend->setBrush(QBrush(QColor(255, 255, 255, 210)));
  p->legend->setBorderPen(QPen(QColor(180, 180, 180)));
  p->legend->setRowSpacing(-2);
  p->axisRect()->insetLayout()->setInsetAlignment(0, Qt::AlignTop | Qt::AlignRight);
  return p;
}

QCPGraph* addGraph(QCustomPlot* p, const QString& name, const QColor& c, Style s, double width) {
  QCPGraph* g = p->addGraph();
  g->setName(name);
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
      // A 2×2-pixel square: readable, and an order of magnitude cheaper than discs at 50k points.
      g->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssSquare, c, c, 1.5));
      break;
    case Style::kStep:
      g->setLineStyle(QCPGraph::lsStepLeft);
      break;
  }
  g->setPen(pen);
  return g;
}

QCPGraph* addGraphRight(QCustomPlot* p, const QString& name, const QColor& c,
                        const QString& rightLabel) {
  QCPGraph* g = p->addGraph(p->xAxis, p->yAxis2);
  g->setName(name);
  QPen pen(c);
  pen.setWidthF(1.0);
  g->setPen(pen);
  p->yAxis2->setVisible(true);
  p->yAxis2->setLabel(rightLabel);
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

// Drawing resolution for decimation: the plot's width in pixels (at least 600, so an export at
// twice the on-screen size still gets one column per two pixels).
int columnsFor(const QCPGraph* g) {
  const int w = g->keyAxis() && g->keyAxis()->axisRect() ? g->keyAxis()->axisRect()->width() : 0;
  return std::max(w, 600);
}

int rowsFor(const QCPGraph* g) {
  const int h = g->valueAxis() && g->valueAxis()->axisRect() ? g->valueAxis()->axisRect()->height() : 0;
  return std::max(h, 300);
}

struct Point {
  double x, y;
};

// Keeps what a raster of `cols` columns can show of a line: per column the first, lowest,
// highest and last point in time order. Exact on screen, and 55k points become a few thousand.
void decimateLine(const std::vector<Point>& in, int cols, QVector<QCPGraphData>& out) {
  const double x0 = in.front().x, span = in.back().x - x0;
  std::size_t i = 0;
  while (i < in.size()) {
    const long col = span > 0 ? static_cast<long>((in[i].x - x0) / span * cols) : 0;
    std::size_t j = i, lo = i, hi = i;
    while (j < in.size() &&
           (span > 0 ? static_cast<long>((in[j].x - x0) / span * cols) : 0) == col) {
      if (in[j].y < in[lo].y) lo = j;
      if (in[j].y > in[hi].y) hi = j;
      ++j;
    }
    std::size_t keep[4] = {i, std::min(lo, hi), std::max(lo, hi), j - 1};
    std::size_t last = static_cast<std::size_t>(-1);
    for (std::size_t k : keep) {
      if (k != last) out.append(QCPGraphData(in[k].x, in[k].y));
      last = k;
    }
    i = j;
  }
}

// Keeps one dot per occupied cell of a cols × rows raster: the same picture with fewer dots
// (a dot is 2 px wide, so cells of 2 × 2 px lose nothing visible).
void decimateDots(const std::vector<Point>& in, int cols, int rows, bool logY,
                  QVector<QCPGraphData>& out) {
  double y0 = in.front().y, y1 = y0;
  for (const auto& p : in) {
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  auto fy = [&](double y) { return logY ? std::log10(y) : y; };
  const double ly0 = fy(y0), lspan = fy(y1) - ly0;
  const double x0 = in.front().x, span = in.back().x - x0;
  std::vector<bool> seen(static_cast<std::size_t>(cols + 1) * (rows + 1), false);
  for (const auto& p : in) {
    const auto c = static_cast<std::size_t>(span > 0 ? (p.x - x0) / span * cols : 0);
    const auto r = static_cast<std::size_t>(lspan > 0 ? (fy(p.y) - ly0) / lspan * rows : 0);
    const std::size_t cell = c * (rows + 1) + r;
    if (!seen[cell]) {
      seen[cell] = true;
      out.append(QCPGraphData(p.x, p.y));
    }
  }
}

}  // namespace

void setSeries(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y,
               std::size_t n, bool skipNaN) {
  n = std::min({n, x.size(), y.size()});
  const bool logY = g->valueAxis()->scaleType() == QCPAxis::stLogarithmic;
  const int cols = columnsFor(g);
  const bool dots = g->lineStyle() == QCPGraph::lsNone;
  QVector<QCPGraphData> data;
  if (n > static_cast<std::size_t>(4 * cols) && skipNaN && g->lineStyle() != QCPGraph::lsStepLeft) {
    std::vector<Point> pts;
    pts.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isfinite(y[i]) && std::isfinite(x[i]) && (!logY || y[i] > 0.0))
        pts.push_back({x[i], y[i]});
    }
    if (pts.size() > static_cast<std::size_t>(4 * cols)) {
      data.reserve(static_cast<qsizetype>(4 * cols));
      if (dots) {
        decimateDots(pts, std::max(cols / 2, 300), std::max(rowsFor(g) / 2, 150), logY, data);
      } else {
        decimateLine(pts, cols, data);
      }
      g->data()->set(data, true);
      return;
    }
  }
  data.reserve(static_cast<qsizetype>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const double v = y[i];
    const bool good = std::isfinite(v) && std::isfinite(x[i]) && (!logY || v > 0.0);
    if (good) {
      data.append(QCPGraphData(x[i], v));
    } else if (!skipNaN && std::isfinite(x[i])) {
      data.append(QCPGraphData(x[i], std::numeric_limits<double>::quiet_NaN()));
    }
  }
  g->data()->set(data, true);
}

Band addBand(QCustomPlot* p, const QString& name, const QColor& c) {
  Band b;
  QColor fill = c;
  fill.setAlpha(50);
  QColor edge = c;
  edge.setAlpha(90);
  b.upper = p->addGraph();
  b.upper->setName(name);
  b.upper->setPen(QPen(edge));
  b.lower = p->addGraph();
  b.lower->setPen(QPen(edge));
  b.lower->setBrush(QBrush(fill));
  b.lower->setChannelFillGraph(b.upper);
  b.lower->removeFromLegend();
  b.upper->setBrush(Qt::NoBrush);
  // Legend swatch shows the fill.
  b.upper->setBrush(Qt::NoBrush);
  return b;
}

void setBand(const Band& b, const std::vector<double>& x, const std::vector<double>& center,
             const std::vector<double>& halfwidth, std::size_t n) {
  n = std::min({n, x.size(), center.size(), halfwidth.size()});
  std::vector<double> lo(n), hi(n);
  for (std::size_t i = 0; i < n; ++i) {
    lo[i] = center[i] - halfwidth[i];
    hi[i] = center[i] + halfwidth[i];
  }
  setBandLimits(b, x, lo, hi, n);
}

// Dense bands are reduced to their per-column envelope (highest upper, lowest lower).
void setBandLimits(const Band& b, const std::vector<double>& x, const std::vector<double>& lo,
                   const std::vector<double>& hi, std::size_t n) {
  n = std::min({n, x.size(), lo.size(), hi.size()});
  const int cols = columnsFor(b.upper);
  QVector<QCPGraphData> u, l;
  const bool dense = n > static_cast<std::size_t>(4 * cols);
  const double x0 = n ? x.front() : 0.0, span = n ? x[n - 1] - x0 : 0.0;
  long col = -1;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || !std::isfinite(x[i])) continue;
    const long c = dense && span > 0 ? static_cast<long>((x[i] - x0) / span * cols) : -2;
    if (dense && c == col && !u.isEmpty()) {
      u.back().value = std::max(u.back().value, hi[i]);
      l.back().value = std::min(l.back().value, lo[i]);
      continue;
    }
    col = c;
    u.append(QCPGraphData(x[i], hi[i]));
    l.append(QCPGraphData(x[i], lo[i]));
  }
  b.upper->data()->set(u, true);
  b.lower->data()->set(l, true);
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

void rescale(QCustomPlot* p, double x0, double x1) {
  p->rescaleAxes(true);
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
  p->replot(QCustomPlot::rpQueuedRefresh);
}

}  // namespace kfw::plot
