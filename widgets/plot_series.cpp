// The series setters of plot_kit.h: dense series reduced to the raster (series_reduce.h), the
// source arrays kept for the readout, dots, tracks and bands.
#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "draw_batch.h"
#include "plot_kit.h"
#include "series_reduce.h"

namespace kfw::plot {

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

// Keeps one dot per occupied cell of a cols × rows raster: the same picture with fewer dots
// (a dot is 2 px wide, so cells of 2 × 2 px lose nothing visible).
void decimateDots(const std::vector<double>& x, const std::vector<double>& y, std::size_t begin,
                  std::size_t n, bool logY, int cols, int rows, QVector<QCPGraphData>& out) {
  auto fy = [logY](double v) { return logY ? coarseLog2(v) : v; };
  // Plain variables, not a structured binding: clang 14 cannot capture one in a lambda.
  const Extent e = extent(x, y, begin, n, logY);
  const double x0 = e.x0, x1 = e.x1, y0 = e.y0, y1 = e.y1;
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

namespace {
// The arrays behind a band, kept on its upper graph (a child object dies with it).
class BandSource : public QObject {
 public:
  using Limits = std::function<void(std::size_t, double&, double&)>;
  explicit BandSource(QCPGraph* upper) : QObject(upper) { setObjectName("kfwBandSource"); }
  void set(const std::vector<double>* x, std::size_t n, Limits limits) {
    x_ = x;
    n_ = n;
    limits_ = std::move(limits);
  }
  bool at(double t, double& lo, double& hi) const {
    if (!x_ || !limits_) return false;
    const auto end = x_->begin() + static_cast<std::ptrdiff_t>(std::min(n_, x_->size()));
    const auto it = std::upper_bound(x_->begin(), end, t);
    if (it == x_->begin()) return false;
    limits_(static_cast<std::size_t>(it - x_->begin()) - 1, lo, hi);
    return true;
  }

 private:
  const std::vector<double>* x_ = nullptr;
  std::size_t n_ = 0;
  Limits limits_;
};

void setBandSource(const Band& b, const std::vector<double>& x, std::size_t n,
                   BandSource::Limits limits) {
  // One per band, made once and updated by every draw (a slider drag redraws every band).
  auto* s = b.upper->findChild<BandSource*>("kfwBandSource", Qt::FindDirectChildrenOnly);
  if (!s) s = new BandSource(b.upper);
  s->set(&x, n, std::move(limits));
}
}  // namespace

bool bandLimitsAt(const QCPGraph* upper, double t, double& lo, double& hi) {
  const auto* s = upper->findChild<BandSource*>("kfwBandSource", Qt::FindDirectChildrenOnly);
  return s && s->at(t, lo, hi);
}

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
  auto data = std::make_shared<QVector<QCPGraphData>>();
  // Dense series are reduced to the raster (lines and steps: first/min/max/last per column;
  // a step graph keeps its level changes to within a column), on either core (draw_batch.h).
  if (n > static_cast<std::size_t>(4 * cols)) {
    // The time span of the drawable points (time is increasing, so the first and last finite x).
    std::size_t a = 0, b = n;
    while (a < n && !std::isfinite(x[a]))
      ++a;
    while (b > a && !std::isfinite(x[b - 1]))
      --b;
    if (b > a) {
      double x0 = x[a], x1 = x[b - 1];
      if (userZoomedX(g->parentPlot())) {
        // Zoomed in: the columns of the visible range (and a point beyond each edge).
        const QCPRange r = g->keyAxis()->range();
        visibleRange(x.data(), a, b, r.lower, r.upper);
        x0 = r.lower;
        x1 = r.upper;
      }
      const int rows = std::max(rowsFor(g) / 2, 150);
      const double* px = x.data();
      const double* py = y.data();
      auto compute = [=] {
        std::vector<XY> reduced;
        reduced.reserve(static_cast<std::size_t>(4 * cols + 8));
        if (dots) {
          reduceDots(px, py, a, b, logY, std::max(cols / 2, 300), rows, reduced);
        } else if (skipNaN) {
          reduceLine(px, py, a, b, logY, x0, x1, cols, reduced);
        } else {
          reduceLineWithGaps(px, py, a, b, logY, x0, x1, cols, reduced);
        }
        data->reserve(static_cast<qsizetype>(reduced.size()));
        for (const XY& p : reduced)
          data->append(QCPGraphData(p.x, p.y));
      };
      submitDraw(g->parentPlot(), compute, [g, data, &x, &y, n] {
        g->data()->set(*data, true);
        setSource(g, &x, &y, n);
      });
      return;
    }
  }
  data->reserve(static_cast<qsizetype>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const double v = y[i];
    const bool good = std::isfinite(v) && std::isfinite(x[i]) && (!logY || v > 0.0);
    if (good) {
      data->append(QCPGraphData(x[i], v));
    } else if (!skipNaN && std::isfinite(x[i])) {
      data->append(QCPGraphData(x[i], std::numeric_limits<double>::quiet_NaN()));
    }
  }
  submitDraw(g->parentPlot(), nullptr, [g, data] {
    setSource(g, nullptr, nullptr, 0);
    g->data()->set(*data, true);
  });
}

void setDots(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = std::min(x.size(), y.size());
  const bool logY = g->valueAxis()->scaleType() == QCPAxis::stLogarithmic;
  auto data = std::make_shared<QVector<QCPGraphData>>();
  const int cols = columnsFor(g), rows = rowsFor(g);
  // Computed at once: callers pass arrays they build for the call.
  if (n > static_cast<std::size_t>(4 * cols)) {
    decimateDots(x, y, 0, n, logY, std::max(cols / 2, 300), std::max(rows / 2, 150), *data);
  } else {
    data->reserve(static_cast<qsizetype>(n));
    forEachPoint(x, y, 0, n, logY,
                 [&](double xi, double yi) { data->append(QCPGraphData(xi, yi)); });
  }
  submitDraw(g->parentPlot(), nullptr, [g, data] { g->data()->set(*data, false); });
}

void setCurve(QCPCurve* c, const std::vector<double>& keys, const std::vector<double>& values,
              std::size_t n) {
  n = std::min({n, keys.size(), values.size()});
  auto d = std::make_shared<QVector<QCPCurveData>>();
  auto compute = [&keys, &values, n, d] {
    const Extent e = extent(keys, values, 0, n, false);
    const double k0 = e.x0, k1 = e.x1, v0 = e.y0, v1 = e.y1;
    // A point is kept when it leaves the last kept point's cell of a grid finer than any pixel
    // raster (1000 cells over the larger extent, about a pixel of an export).
    const double cell = std::max(k1 - k0, v1 - v0) / 1000.0;
    const double inv = cell > 0 ? 1.0 / cell : 0.0;
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
      d->append(QCPCurveData(static_cast<double>(d->size()), k, v));
      last_k = ck;
      last_v = cv;
      pending = false;
    });
    if (pending) d->append(QCPCurveData(static_cast<double>(d->size()), last_key, last_value));
  };
  submitDraw(c->parentPlot(), compute, [c, d] { c->data()->set(*d, true); });
}

namespace {

// Fills a band from per-step limits (limits(i, lo, hi)); dense bands are reduced to their
// per-column envelope (highest upper, lowest lower).
// `finish` turns the reduced limits into the band's edges (the identity for most bands).
// `gaps`: a step with a non-finite limit breaks the band (a NaN point) instead of being left out.
template <typename Limits, typename Finish = void (*)(std::vector<XY>&, std::vector<XY>&)>
void fillBand(
    const Band& b, const std::vector<double>& x, std::size_t n, Limits limits,
    Finish finish = [](std::vector<XY>&, std::vector<XY>&) {}, bool gaps = false) {
  const int cols = columnsFor(b.upper);
  std::size_t begin = 0, end = n;
  double x0 = n ? x.front() : 0.0, x1 = n ? x[n - 1] : 0.0;
  if (n <= static_cast<std::size_t>(4 * cols)) {
    x1 = x0;  // sparse: every step its own point
  } else if (userZoomedX(b.upper->parentPlot())) {
    // Zoomed in: the columns of the visible range (and a point beyond each edge).
    const QCPRange r = b.upper->keyAxis()->range();
    visibleRange(x.data(), begin, end, r.lower, r.upper);
    x0 = r.lower;
    x1 = r.upper;
  }
  auto u = std::make_shared<QVector<QCPGraphData>>(), l = std::make_shared<QVector<QCPGraphData>>();
  auto compute = [=, &x] {
    std::vector<XY> up, lo;
    const std::size_t cap = x1 > x0 ? static_cast<std::size_t>(cols + 4) : n;
    up.reserve(cap);
    lo.reserve(cap);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (x1 > x0 && gaps) {
      // Each run between gaps reduced on its own, a NaN point between runs.
      std::size_t s = begin;
      while (s < end) {
        std::size_t e = s;
        double lo_e = 0.0, hi_e = 0.0;
        while (e < end && (limits(e, lo_e, hi_e), drawable(lo_e, false) && drawable(hi_e, false)))
          ++e;
        if (e > s) reduceBand(x.data(), s, e, x0, x1, cols, limits, up, lo);
        if (e < end && std::isfinite(x[e]) && !up.empty() && std::isfinite(up.back().y)) {
          up.push_back({x[e], nan});
          lo.push_back({x[e], nan});
        }
        s = e + 1;
      }
    } else if (x1 > x0) {
      reduceBand(x.data(), begin, end, x0, x1, cols, limits, up, lo);
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        double lo_i = 0.0, hi_i = 0.0;
        limits(i, lo_i, hi_i);
        if (!std::isfinite(x[i])) continue;
        if (!drawable(lo_i, false) || !drawable(hi_i, false)) {
          if (gaps && !up.empty() && std::isfinite(up.back().y)) {
            up.push_back({x[i], nan});
            lo.push_back({x[i], nan});
          }
          continue;
        }
        up.push_back({x[i], hi_i});
        lo.push_back({x[i], lo_i});
      }
    }
    finish(up, lo);
    auto put = [](QVector<QCPGraphData>& d, const std::vector<XY>& v) {
      d.reserve(static_cast<qsizetype>(v.size()));
      for (const XY& p : v)
        d.append(QCPGraphData(p.x, p.y));
    };
    put(*u, up);
    put(*l, lo);
  };
  const bool dense = x1 > x0;  // sparse bands are computed at once
  if (!dense) compute();
  submitDraw(b.upper->parentPlot(), dense ? std::function<void()>(compute) : nullptr, [b, u, l] {
    b.upper->data()->set(*u, true);
    b.lower->data()->set(*l, true);
  });
}

}  // namespace

void setBand(const Band& b, const std::vector<double>& x, const std::vector<double>& center,
             const std::vector<double>& halfwidth, std::size_t n) {
  n = std::min({n, x.size(), center.size(), halfwidth.size()});
  auto limits = [c = center.data(), h = halfwidth.data()](std::size_t i, double& lo, double& hi) {
    lo = c[i] - h[i];
    hi = c[i] + h[i];
  };
  setBandSource(b, x, n, limits);
  fillBand(b, x, n, limits);
}

void setSigmaBand(const Band& b, const std::vector<double>& x, const std::vector<double>* center,
                  const std::vector<double>& variance, double k, std::size_t n) {
  n = std::min({n, x.size(), variance.size(), center ? center->size() : n});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double* c = center ? center->data() : nullptr;
  auto exact = [c, var = variance.data(), k, nan](std::size_t i, double& lo, double& hi) {
    const double half = var[i] >= 0.0 ? k * std::sqrt(var[i]) : nan;
    const double mid = c ? c[i] : 0.0;
    lo = mid - half;
    hi = mid + half;
  };
  setBandSource(b, x, n, exact);
  if (!center) {
    // 0 ± k·√v: the envelope of a column is ± k·√(its largest v), one square root a column.
    fillBand(
        b, x, n,
        [var = variance.data(), nan](std::size_t i, double& lo, double& hi) {
          const double v = var[i];
          hi = v >= 0.0 ? v : nan;
          lo = -hi;
        },
        [k](std::vector<XY>& up, std::vector<XY>& lo) {
          for (std::size_t i = 0; i < up.size(); ++i) {
            up[i].y = k * std::sqrt(up[i].y);
            lo[i].y = -up[i].y;
          }
        });
    return;
  }
  fillBand(b, x, n, exact);
}

void setBandLimits(const Band& b, const std::vector<double>& x, const std::vector<double>& lo,
                   const std::vector<double>& hi, std::size_t n, bool gaps) {
  n = std::min({n, x.size(), lo.size(), hi.size()});
  auto limits = [pl = lo.data(), ph = hi.data()](std::size_t i, double& l, double& h) {
    l = pl[i];
    h = ph[i];
  };
  setBandSource(b, x, n, limits);
  fillBand(
      b, x, n, limits, [](std::vector<XY>&, std::vector<XY>&) {}, gaps);
}

}  // namespace kfw::plot
