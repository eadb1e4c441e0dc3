// The trajectory block: one state against another (a top view) — the true track, the estimated
// track up to the replay cursor with a mark at the cursor, and labelled fixed points (beacons)
// whose coordinates the engine evaluated at the run's values (model::trajectory_block_data).
#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "plot_kit.h"
#include "plot_text.h"
#include "plots/block_drawer.h"

namespace kfw::plot {

namespace {

QCPCurve* addTrack(QCustomPlot* p, const QString& name, const QColor& c) {
  auto* curve = new QCPCurve(p->xAxis, p->yAxis);
  curve->setName(typeset(name));
  curve->setPen(QPen(c));
  return curve;
}

class TrajectoryBlock final : public BlockDrawer {
 public:
  TrajectoryBlock(QWidget* parent, const model::PlotBlockSpec& b) : block_(b) {
    const QString x = QString::fromStdString(b.tx.label), y = QString::fromStdString(b.ty.label);
    title_ = panelTitle(b.title, QString("%1 against %2: true and estimated track").arg(y, x));
    plot_ = makePlot(parent, title_, withUnit(x, b.tx.unit), withUnit(y, b.ty.unit));
    truth_ = addTrack(plot_, "truth", color::kTruth);
    estimate_ = addTrack(plot_, "estimate", color::kEstimate);
    here_ = plot_->addGraph();
    here_->setName("estimate at cursor");
    here_->setLineStyle(QCPGraph::lsNone);
    here_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, QPen(color::kEstimate, 2),
                                           QBrush(Qt::white), 8));
    points_ = plot_->addGraph();
    points_->setName("fixed points");
    points_->setLineStyle(QCPGraph::lsNone);
    points_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssDiamond, QPen(color::kSecond, 2),
                                             QBrush(color::kSecond), 9));
    if (b.points.empty()) points_->removeFromLegend();
    if (b.equal_scale) {
      // At whatever size the plot is drawn (window, export): after every layout.
      QObject::connect(plot_, &QCustomPlot::afterLayout, plot_, [this] { equalScale(); });
    }
  }

  QCustomPlot* plot() const override { return plot_; }
  QString title() const override { return title_; }

  void setResult(const BlockInput& in) override {
    data_ = model::trajectory_block_data(block_, in.result);
    if (data_.x_true) {
      setCurve(truth_, *data_.x_true, *data_.y_true, kAll);
    } else {
      truth_->data()->clear();
    }
    points_->data()->clear();
    for (auto* l : labels_)
      plot_->removeItem(l);
    labels_.clear();
    // Each label on the side of its point that faces the middle of the points, so that a point
    // at the edge of the view keeps its label inside.
    double cx = 0.0, cy = 0.0;
    for (const auto& p : data_.points) {
      cx += p.x / static_cast<double>(data_.points.size());
      cy += p.y / static_cast<double>(data_.points.size());
    }
    for (const auto& p : data_.points) {
      points_->addData(p.x, p.y);
      auto* label = new QCPItemText(plot_);
      label->setText(QString::fromStdString(p.name));
      label->setColor(color::kSecond);
      label->setFont(QFont(plot_->font().family(), 8));
      const bool right = p.x >= cx, top = p.y >= cy;  // the y axis points up
      label->setPositionAlignment((right ? Qt::AlignRight : Qt::AlignLeft) |
                                  (top ? Qt::AlignTop : Qt::AlignBottom));
      label->position->setCoords(p.x, p.y);
      label->setPadding(QMargins(right ? 0 : 6, top ? 4 : 0, right ? 6 : 0, top ? 0 : 4));
      labels_.push_back(label);
    }
    fit();
  }

  void setGhosts(const std::vector<Ghost>& ghosts) override {
    for (auto& g : ghosts_)
      plot_->removePlottable(g.curve);
    ghosts_.clear();
    int i = 0;
    for (const auto& [name, r] : ghosts) {
      auto d = model::trajectory_block_data(block_, *r);
      if (!d.x || !d.y) continue;
      auto* c = addTrack(plot_, "estimate [pinned: " + name + "]", color::ghost(i++));
      c->setPen(QPen(c->pen().color(), 1, Qt::DashLine));
      ghosts_.push_back({c, &r->t, d});
    }
  }

  void draw(const Frame& f) override {
    if (!data_.x || !data_.y) return;
    for (const auto& g : ghosts_)
      setCurve(g.curve, *g.data.x, *g.data.y, f.all ? kAll : stepsUpTo(*g.t, f));
    setCurve(estimate_, *data_.x, *data_.y, f.n);
    here_->data()->clear();
    const std::size_t n = std::min(f.n, data_.x->size());
    if (!f.all && n > 0) here_->addData((*data_.x)[n - 1], (*data_.y)[n - 1]);
    replot(plot_);
  }

 private:
  // Both axes to every track and fixed point with a margin, unless the user zoomed.
  void fit() {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    const auto take = [&](double x, double y) {
      if (!std::isfinite(x) || !std::isfinite(y)) return;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    };
    for (std::size_t k = 0; data_.x && k < data_.x->size(); ++k)
      take((*data_.x)[k], (*data_.y)[k]);
    for (std::size_t k = 0; data_.x_true && k < data_.x_true->size(); ++k)
      take((*data_.x_true)[k], (*data_.y_true)[k]);
    for (const auto& p : data_.points)
      take(p.x, p.y);
    if (!(x0 <= x1 && y0 <= y1)) return;
    const double mx = std::max(0.06 * (x1 - x0), 1e-9), my = std::max(0.06 * (y1 - y0), 1e-9);
    box_ = QRectF(QPointF(x0 - mx, y0 - my), QPointF(x1 + mx, y1 + 2 * my));
    if (!userZoomedX(plot_)) plot_->xAxis->setRange(box_.left(), box_.right());
    if (!userZoomedY(plot_)) plot_->yAxis->setRange(box_.top(), box_.bottom());
  }

  // Equal scale ("equal_scale"): the fitted box (or the user's zoom) inside the axis rect, the
  // roomier axis widened about its centre, laid out again while the tick labels move the margins.
  void equalScale() {
    if (fitting_) return;
    fitting_ = true;
    QCPAxisRect* ar = plot_->axisRect();
    for (int pass = 0; pass < 3; ++pass) {
      const int w = ar->width(), h = ar->height();
      if (w <= 0 || h <= 0) break;
      const QCPRange x = plot_->xAxis->range(), y = plot_->yAxis->range();
      const bool fitted = !userZoomedX(plot_) && !userZoomedY(plot_) && box_.isValid();
      const double wx = fitted ? box_.width() : x.size(), wy = fitted ? box_.height() : y.size();
      const double cx = fitted ? box_.center().x() : x.center();
      const double cy = fitted ? box_.center().y() : y.center();
      const double per_px = std::max(wx / w, wy / h);
      plot_->xAxis->setRange(cx - 0.5 * w * per_px, cx + 0.5 * w * per_px);
      plot_->yAxis->setRange(cy - 0.5 * h * per_px, cy + 0.5 * h * per_px);
      for (auto phase : {QCPLayoutElement::upPreparation, QCPLayoutElement::upMargins,
                         QCPLayoutElement::upLayout}) {
        plot_->plotLayout()->update(phase);
      }
      if (ar->width() == w && ar->height() == h) break;
    }
    fitting_ = false;
  }

  struct GhostTrack {
    QCPCurve* curve = nullptr;
    const std::vector<double>* t = nullptr;
    model::TrajectoryData data;
  };

  model::PlotBlockSpec block_;
  QString title_;
  QCustomPlot* plot_ = nullptr;
  QCPCurve *truth_ = nullptr, *estimate_ = nullptr;
  std::vector<GhostTrack> ghosts_;
  QCPGraph *here_ = nullptr, *points_ = nullptr;
  std::vector<QCPItemText*> labels_;
  model::TrajectoryData data_;
  QRectF box_;  // the fitted ranges: x from left to right, y from top to bottom
  bool fitting_ = false;
};

}  // namespace

std::unique_ptr<BlockDrawer> makeTrajectoryBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                 const Scenario&) {
  return std::make_unique<TrajectoryBlock>(parent, b);
}

}  // namespace kfw::plot
