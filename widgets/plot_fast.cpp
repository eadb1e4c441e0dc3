#include "plot_fast.h"

#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace kfw::plot {

namespace {

// True where the painter draws the screen's look (no antialiasing, raster, not for export).
bool screenPainter(const QCPPainter* painter) {
  return !painter->antialiasing() && !painter->modes().testFlag(QCPPainter::pmVectorized) &&
         !painter->modes().testFlag(QCPPainter::pmNoCaching);
}

class BandFill final : public QCPGraph {
 public:
  using QCPGraph::QCPGraph;

 protected:
  void draw(QCPPainter* painter) override {
    if (!screenPainter(painter) || brush().style() == Qt::NoBrush || !drawSpans(painter)) {
      QCPGraph::draw(painter);
      return;
    }
    // The edges as usual, without QCustomPlot's polygon fill.
    const QBrush b = brush();
    setBrush(Qt::NoBrush);
    QCPGraph::draw(painter);
    setBrush(b);
  }

 private:
  // The fill one pixel column at a time; false (nothing drawn) where the points are sparse (the
  // polygon is cheap there) or the edges do not share their keys.
  bool drawSpans(QCPPainter* painter) {
    QCPGraph* upper = channelFillGraph();
    QCPAxis *kx = keyAxis(), *vy = valueAxis();
    if (!upper || !kx || !vy || upper->valueAxis() != vy || upper->keyAxis() != kx) return false;
    const auto lo = data(), hi = upper->data();
    const int n = lo->size();
    if (n < 2 || hi->size() != n || kx->orientation() != Qt::Horizontal) return false;
    const QRect area = kx->axisRect()->rect();
    // Dense: at most 3 px a segment on average over the visible range.
    const double span =
        std::abs(kx->coordToPixel(lo->at(n - 1)->key) - kx->coordToPixel(lo->at(0)->key));
    const double visible = std::min(span, static_cast<double>(area.width()));
    if (visible <= 0 || span / (n - 1) > 3.0) return false;
    x_.resize(static_cast<std::size_t>(n));
    top_.resize(static_cast<std::size_t>(n));
    bottom_.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const auto l = lo->at(i);
      const auto h = hi->at(i);
      if (l->key != h->key) return false;
      const double yl = vy->coordToPixel(l->value), yh = vy->coordToPixel(h->value);
      const auto k = static_cast<std::size_t>(i);
      x_[k] = kx->coordToPixel(l->key);
      top_[k] = std::clamp(std::min(yl, yh), -1e6, 1e6);
      bottom_[k] = std::clamp(std::max(yl, yh), -1e6, 1e6);
    }
    painter->setPen(Qt::NoPen);
    const QBrush b = brush();
    // The polygon's pixels: per pixel column, the rows whose centres lie between the edges
    // interpolated at the column's centre (what Qt's filler does without antialiasing).
    for (std::size_t i = 0; i + 1 < x_.size(); ++i) {
      std::size_t a = i, z = i + 1;
      if (x_[a] > x_[z]) std::swap(a, z);
      const double xa = x_[a], xz = x_[z];
      const long c0 = std::max<long>(std::lround(xa), area.left() - 1);
      const long c1 = std::min<long>(std::lround(xz), area.right() + 2);
      for (long c = c0; c < c1; ++c) {
        const double f = xz > xa ? std::clamp((c + 0.5 - xa) / (xz - xa), 0.0, 1.0) : 0.0;
        const double top = top_[a] + f * (top_[z] - top_[a]);
        const double bottom = bottom_[a] + f * (bottom_[z] - bottom_[a]);
        const auto y0 = static_cast<int>(std::ceil(top - 0.5));
        const auto y1 = static_cast<int>(std::floor(bottom - 0.5)) + 1;
        if (y1 > y0) painter->fillRect(QRect(static_cast<int>(c), y0, 1, y1 - y0), b);
      }
    }
    return true;
  }

  std::vector<double> x_, top_, bottom_;
};

class DotGraph final : public QCPGraph {
 public:
  using QCPGraph::QCPGraph;

 protected:
  void draw(QCPPainter* painter) override {
    const QCPScatterStyle& s = scatterStyle();
    if (!screenPainter(painter) || s.shape() != QCPScatterStyle::ssPixmap ||
        lineStyle() != lsNone || !keyAxis() || !valueAxis() ||
        keyAxis()->orientation() != Qt::Horizontal) {
      QCPGraph::draw(painter);
      return;
    }
    const QRect area = keyAxis()->axisRect()->rect();
    if (area.isEmpty()) return;
    if (image_.size() != area.size()) {
      image_ = QImage(area.size(), QImage::Format_ARGB32_Premultiplied);
    }
    image_.fill(0);
    // The dot's colour: the scatter pixmap is one colour (plot_kit.cpp's dotStyle).
    const QImage dot = s.pixmap().toImage().convertToFormat(QImage::Format_ARGB32_Premultiplied);
    const QRgb c = dot.isNull() ? qPremultiply(pen().color().rgba()) : dot.pixel(0, 0);
    const int dw = std::max(dot.width(), 1), dh = std::max(dot.height(), 1);
    // QCustomPlot draws scatters with their own antialiasing hint: when on, the painter is
    // shifted by half a pixel and each dot lands one pixel right and down. The same here.
    applyScattersAntialiasingHint(painter);
    const long shift = painter->antialiasing() ? 1 : 0;
    painter->setAntialiasing(false);
    const int w = area.width(), h = area.height();
    auto* bits = reinterpret_cast<QRgb*>(image_.bits());
    const auto stride = static_cast<std::ptrdiff_t>(image_.bytesPerLine() / 4);
    QCPAxis *kx = keyAxis(), *vy = valueAxis();
    for (auto it = data()->constBegin(); it != data()->constEnd(); ++it) {
      const double px = kx->coordToPixel(it->key), py = vy->coordToPixel(it->value);
      if (!(std::isfinite(px) && std::isfinite(py))) continue;
      // As QCPScatterStyle places a pixmap: centred, rounded to the pixel.
      const long x0 = std::lround(px - dw / 2.0) + shift - area.left();
      const long y0 = std::lround(py - dh / 2.0) + shift - area.top();
      if (x0 + dw <= 0 || y0 + dh <= 0 || x0 >= w || y0 >= h) continue;
      for (long y = std::max(y0, 0L); y < std::min<long>(y0 + dh, h); ++y) {
        QRgb* row = bits + y * stride;
        for (long x = std::max(x0, 0L); x < std::min<long>(x0 + dw, w); ++x)
          row[x] = c;
      }
    }
    painter->drawImage(area.topLeft(), image_);
  }

 private:
  QImage image_;
};

}  // namespace

QCPGraph* newBandFill(QCPAxis* key, QCPAxis* value) {
  return new BandFill(key, value);
}

QCPGraph* newDotGraph(QCPAxis* key, QCPAxis* value) {
  return new DotGraph(key, value);
}

}  // namespace kfw::plot
