#include "plot_kit.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

namespace {
// Wraps the legend into as many columns as the plot's width holds (entries fill rows first).
void fitLegend(QCustomPlot* p) {
  QCPLegend* l = p->legend;
  // Only the legend in makePlot's row (a view may have moved it beside the plot).
  if (!l || !l->visible() || l->layout() != p->plotLayout()) return;
  int widest = 1;
  for (int i = 0; i < l->itemCount(); ++i) {
    if (QCPAbstractLegendItem* item = l->item(i))  // null: an empty cell of the grid
      widest = std::max(widest, item->minimumOuterSizeHint().width());
  }
  const int room = std::max(1, p->width() - 16);
  const int cols = std::max(1, room / (widest + l->columnSpacing()));
  if (l->wrap() != cols || l->fillOrder() != QCPLayoutGrid::foColumnsFirst) {
    l->setWrap(cols);
    l->setFillOrder(QCPLayoutGrid::foColumnsFirst, true);
  }
}
}  // namespace

QCustomPlot* makePlot(QWidget* parent, const QString& title, const QString& xLabel,
                      const QString& yLabel) {
  auto* p = new QCustomPlot(parent);
  p->setMinimumHeight(240);
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
  QObject::connect(p, &QCustomPlot::beforeReplot, p, [p] { fitLegend(p); });
  return p;
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
  const int h =
      g->valueAxis() && g->valueAxis()->axisRect() ? g->valueAxis()->axisRect()->height() : 0;
  return std::max(h, 300);
}

// Cheap log2 for binning dots on a log axis: exponent plus a linear mantissa, within 0.09 of
// log2. Binning only chooses which dots share a 2 × 2-pixel cell; every dot drawn is exact.
double fastLog2(double y) {
  int e = 0;
  const double m = std::frexp(y, &e);  // y = m·2^e, m in [0.5, 1)
  return static_cast<double>(e) + 2.0 * m - 2.0;
}

// The finite, drawable points among the first n, visited in order.
template <typename F>
void forEachPoint(const std::vector<double>& x, const std::vector<double>& y, std::size_t begin,
                  std::size_t n, bool logY, F&& f) {
  for (std::size_t i = begin; i < n; ++i) {
    const double xi = x[i], yi = y[i];
    if (std::isfinite(xi) && std::isfinite(yi) && (!logY || yi > 0.0)) f(xi, yi);
  }
}

// The bounding box of the drawable points among the first n; x0 > x1 when there are none.
struct Extent {
  double x0, x1, y0, y1;
};
Extent extent(const std::vector<double>& x, const std::vector<double>& y, std::size_t begin,
              std::size_t n, bool logY) {
  const double inf = std::numeric_limits<double>::infinity();
  Extent e{inf, -inf, inf, -inf};
  forEachPoint(x, y, begin, n, logY, [&](double xi, double yi) {
    e.x0 = std::min(e.x0, xi);
    e.x1 = std::max(e.x1, xi);
    e.y0 = std::min(e.y0, yi);
    e.y1 = std::max(e.y1, yi);
  });
  return e;
}

// Keeps what a raster of `cols` columns can show of a line: per column the first, lowest,
// highest and last point in time order. Exact on screen, and 55k points become a few thousand.
void decimateLine(const std::vector<double>& x, const std::vector<double>& y, std::size_t begin,
                  std::size_t n, bool logY, double x0, double x1, int cols,
                  QVector<QCPGraphData>& out) {
  const double scale = x1 > x0 ? cols / (x1 - x0) : 0.0;
  long col = -1;
  QCPGraphData first, lo, hi, last;
  std::size_t count = 0;
  auto flush = [&] {
    if (count == 0) return;
    out.append(first);
    const bool lo_first = lo.key <= hi.key;
    const QCPGraphData& a = lo_first ? lo : hi;
    const QCPGraphData& b = lo_first ? hi : lo;
    if (a.key != first.key || a.value != first.value) out.append(a);
    if (b.key != a.key || b.value != a.value) out.append(b);
    if (count > 1 && (last.key != b.key || last.value != b.value)) out.append(last);
  };
  forEachPoint(x, y, begin, n, logY, [&](double xi, double yi) {
    const long c = static_cast<long>((xi - x0) * scale);
    const QCPGraphData p(xi, yi);
    if (c != col) {
      flush();
      col = c;
      first = lo = hi = last = p;
      count = 1;
      return;
    }
    if (yi < lo.value) lo = p;
    if (yi > hi.value) hi = p;
    last = p;
    ++count;
  });
  flush();
}

// Keeps one dot per occupied cell of a cols × rows raster: the same picture with fewer dots
// (a dot is 2 px wide, so cells of 2 × 2 px lose nothing visible).
void decimateDots(const std::vector<double>& x, const std::vector<double>& y, std::size_t begin,
                  std::size_t n, bool logY, int cols, int rows, QVector<QCPGraphData>& out) {
  auto fy = [logY](double v) { return logY ? fastLog2(v) : v; };
  const auto [x0, x1, y0, y1] = extent(x, y, begin, n, logY);
  if (x0 > x1) return;
  const double fy0 = fy(y0), fspan = fy(y1) - fy0;
  const double cscale = x1 > x0 ? cols / (x1 - x0) : 0.0;
  const double rscale = fspan > 0 ? rows / fspan : 0.0;
  std::vector<unsigned char> seen(static_cast<std::size_t>(cols + 1) * (rows + 1), 0);
  forEachPoint(x, y, begin, n, logY, [&](double xi, double yi) {
    const auto c = std::clamp(static_cast<long>((xi - x0) * cscale), 0L, static_cast<long>(cols));
    const auto r =
        std::clamp(static_cast<long>((fy(yi) - fy0) * rscale), 0L, static_cast<long>(rows));
    unsigned char& s = seen[static_cast<std::size_t>(c * (rows + 1) + r)];
    if (!s) {
      s = 1;
      out.append(QCPGraphData(xi, yi));
    }
  });
}

// The dot raster of a graph: 2 × 2-pixel cells of its axis rect.
void decimateDotsFor(const QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y,
                     std::size_t begin, std::size_t n, bool logY, QVector<QCPGraphData>& out) {
  decimateDots(x, y, begin, n, logY, std::max(columnsFor(g) / 2, 300),
               std::max(rowsFor(g) / 2, 150), out);
}

}  // namespace

namespace {
const char* const kSrcX = "kfwSrcX";
const char* const kSrcY = "kfwSrcY";
const char* const kSrcN = "kfwSrcN";
void setSource(QCPGraph* g, const std::vector<double>* x, const std::vector<double>* y,
               std::size_t n) {
  g->setProperty(kSrcX, QVariant::fromValue(reinterpret_cast<quintptr>(x)));
  g->setProperty(kSrcY, QVariant::fromValue(reinterpret_cast<quintptr>(y)));
  g->setProperty(kSrcN, QVariant::fromValue(static_cast<qulonglong>(n)));
}
}  // namespace

SeriesSource seriesSource(const QCPGraph* g) {
  SeriesSource s;
  s.x = reinterpret_cast<const std::vector<double>*>(g->property(kSrcX).value<quintptr>());
  s.y = reinterpret_cast<const std::vector<double>*>(g->property(kSrcY).value<quintptr>());
  s.n = static_cast<std::size_t>(g->property(kSrcN).toULongLong());
  if (!s.x || !s.y) return {};
  return s;
}

void setSeries(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y,
               std::size_t n, bool skipNaN) {
  n = std::min({n, x.size(), y.size()});
  const bool logY = g->valueAxis()->scaleType() == QCPAxis::stLogarithmic;
  const int cols = columnsFor(g);
  const bool dots = g->lineStyle() == QCPGraph::lsNone;
  QVector<QCPGraphData> data;
  if (n > static_cast<std::size_t>(4 * cols) && skipNaN && g->lineStyle() != QCPGraph::lsStepLeft) {
    // The time span of the drawable points (time is increasing, so the first and last finite x).
    std::size_t a = 0, b = n;
    while (a < n && !std::isfinite(x[a]))
      ++a;
    while (b > a && !std::isfinite(x[b - 1]))
      --b;
    if (b > a) {
      data.reserve(static_cast<qsizetype>(4 * cols + 4));
      // Zoomed in: the columns of the visible range (and a point beyond each edge).
      double x0 = x[a], x1 = x[b - 1];
      if (userZoomedX(g->parentPlot())) {
        const QCPRange r = g->keyAxis()->range();
        const auto first = x.begin() + static_cast<std::ptrdiff_t>(a);
        const auto last = x.begin() + static_cast<std::ptrdiff_t>(b);
        auto lo = std::lower_bound(first, last, r.lower);
        auto hi = std::upper_bound(lo, last, r.upper);
        if (lo != first) --lo;
        if (hi != last) ++hi;
        a = static_cast<std::size_t>(lo - x.begin());
        b = static_cast<std::size_t>(hi - x.begin());
        x0 = r.lower;
        x1 = r.upper;
      }
      if (dots) {
        decimateDotsFor(g, x, y, a, b, logY, data);
      } else {
        decimateLine(x, y, a, b, logY, x0, x1, cols, data);
      }
      g->data()->set(data, true);
      setSource(g, &x, &y, n);
      return;
    }
  }
  setSource(g, nullptr, nullptr, 0);
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
    painter->setPen(QPen(pen().color().darker(130)));
    painter->setBrush(f);
    painter->drawRect(rect.adjusted(1.0, 2.0, -1.0, -2.0));
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
  b.upper->setName(name);
  b.upper->addToLegend();
  b.upper->setPen(QPen(edge));
  b.upper->setBrush(Qt::NoBrush);
  b.lower = p->addGraph();
  b.lower->setPen(QPen(edge));
  b.lower->setBrush(QBrush(fill));
  b.lower->setChannelFillGraph(b.upper);
  b.lower->setName("");  // the band is named by its upper edge
  b.lower->removeFromLegend();
  return b;
}

void setDots(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = std::min(x.size(), y.size());
  const bool logY = g->valueAxis()->scaleType() == QCPAxis::stLogarithmic;
  QVector<QCPGraphData> data;
  if (n > static_cast<std::size_t>(4 * columnsFor(g))) {
    decimateDotsFor(g, x, y, 0, n, logY, data);
  } else {
    data.reserve(static_cast<qsizetype>(n));
    forEachPoint(x, y, 0, n, logY,
                 [&](double xi, double yi) { data.append(QCPGraphData(xi, yi)); });
  }
  g->data()->set(data, false);
}

void setCurve(QCPCurve* c, const std::vector<double>& keys, const std::vector<double>& values,
              std::size_t n) {
  n = std::min({n, keys.size(), values.size()});
  const auto [k0, k1, v0, v1] = extent(keys, values, 0, n, false);
  // A point is kept when it leaves the last kept point's cell of a grid finer than any pixel
  // raster (1000 cells over the larger extent, about a pixel of an export).
  const double cell = std::max(k1 - k0, v1 - v0) / 1000.0;
  const double inv = cell > 0 ? 1.0 / cell : 0.0;
  QVector<QCPCurveData> d;
  long last_k = std::numeric_limits<long>::min(), last_v = last_k;
  double last_key = 0.0, last_value = 0.0;
  bool pending = false;
  forEachPoint(keys, values, 0, n, false, [&](double k, double v) {
    const long ck = static_cast<long>((k - k0) * inv), cv = static_cast<long>((v - v0) * inv);
    if (ck == last_k && cv == last_v) {
      last_key = k;
      last_value = v;
      pending = true;
      return;
    }
    d.append(QCPCurveData(static_cast<double>(d.size()), k, v));
    last_k = ck;
    last_v = cv;
    pending = false;
  });
  if (pending) d.append(QCPCurveData(static_cast<double>(d.size()), last_key, last_value));
  c->data()->set(d, true);
}

namespace {

// Fills a band from per-step limits lo(i), hi(i); dense bands are reduced to their per-column
// envelope (highest upper, lowest lower).
template <typename Lo, typename Hi>
void fillBand(const Band& b, const std::vector<double>& x, std::size_t n, Lo&& lo, Hi&& hi) {
  const int cols = columnsFor(b.upper);
  const bool dense = n > static_cast<std::size_t>(4 * cols);
  QVector<QCPGraphData> u, l;
  const qsizetype cap = static_cast<qsizetype>(dense ? cols + 2 : n);
  u.reserve(cap);
  l.reserve(cap);
  double x0 = n ? x.front() : 0.0, span = n ? x[n - 1] - x0 : 0.0;
  std::size_t begin = 0, end = n;
  if (dense && userZoomedX(b.upper->parentPlot())) {
    // Zoomed in: the columns of the visible range (and a point beyond each edge).
    const QCPRange r = b.upper->keyAxis()->range();
    const auto last = x.begin() + static_cast<std::ptrdiff_t>(n);
    auto from = std::lower_bound(x.begin(), last, r.lower);
    auto to = std::upper_bound(from, last, r.upper);
    if (from != x.begin()) --from;
    if (to != last) ++to;
    begin = static_cast<std::size_t>(from - x.begin());
    end = static_cast<std::size_t>(to - x.begin());
    x0 = r.lower;
    span = r.size();
  }
  const double scale = dense && span > 0 ? cols / span : 0.0;
  long col = -1;
  for (std::size_t i = begin; i < end; ++i) {
    const double lo_i = lo(i), hi_i = hi(i);
    if (!std::isfinite(lo_i) || !std::isfinite(hi_i) || !std::isfinite(x[i])) continue;
    const long c = scale > 0 ? static_cast<long>((x[i] - x0) * scale) : -2;
    if (scale > 0 && c == col && !u.isEmpty()) {
      u.back().value = std::max(u.back().value, hi_i);
      l.back().value = std::min(l.back().value, lo_i);
      continue;
    }
    col = c;
    u.append(QCPGraphData(x[i], hi_i));
    l.append(QCPGraphData(x[i], lo_i));
  }
  b.upper->data()->set(u, true);
  b.lower->data()->set(l, true);
}

}  // namespace

void setBand(const Band& b, const std::vector<double>& x, const std::vector<double>& center,
             const std::vector<double>& halfwidth, std::size_t n) {
  n = std::min({n, x.size(), center.size(), halfwidth.size()});
  fillBand(
      b, x, n, [&](std::size_t i) { return center[i] - halfwidth[i]; },
      [&](std::size_t i) { return center[i] + halfwidth[i]; });
}

void setBandLimits(const Band& b, const std::vector<double>& x, const std::vector<double>& lo,
                   const std::vector<double>& hi, std::size_t n) {
  n = std::min({n, x.size(), lo.size(), hi.size()});
  fillBand(
      b, x, n, [&](std::size_t i) { return lo[i]; }, [&](std::size_t i) { return hi[i]; });
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

void rescale(QCustomPlot* p, double x0, double x1, double settle) {
  if (x1 > x0) p->setProperty(kTime, true);
  const bool keep_x = userZoomedX(p), keep_y = userZoomedY(p);
  if (keep_x && keep_y) return;
  const QCPRange xr = p->xAxis->range(), yr = p->yAxis->range(), y2r = p->yAxis2->range();
  rescaleAuto(p, x0, x1, settle);
  if (keep_x) p->xAxis->setRange(xr);
  if (keep_y) {
    p->yAxis->setRange(yr);
    p->yAxis2->setRange(y2r);
  }
}

void rescaleAuto(QCustomPlot* p, double x0, double x1, double settle) {
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
  p->replot(QCustomPlot::rpQueuedRefresh);
}

}  // namespace kfw::plot
