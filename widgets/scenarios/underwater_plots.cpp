// Plots of the `underwater` scenario (seed 004): top-view trajectory (command, truth, estimate,
// beacons), distance error, range innovations with ±2√S and gated samples, a per-sensor timing
// raster, and the 5 × 5 covariance of the simulated errors beside the design values. Pinned
// snapshots add their estimated track and distance error as faded ghosts.
#include <qcustomplot.h>

#include <QFontMetrics>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "plot_kit.h"
#include "scenario_view.h"
#include "scenarios/underwater/underwater_ekf.h"
#include "scenarios/underwater/underwater_sim.h"
#include "scenarios/underwater/underwater_stats.h"

namespace kfw {

namespace {

using underwater::UnderwaterResult;

// Dense tracks keep 1-px pens (wider ones go through Qt's stroker).
QCPCurve* addCurve(QCustomPlot* p, const QString& name, const QColor& c, plot::Style s,
                   double width = 1.0) {
  auto* curve = new QCPCurve(p->xAxis, p->yAxis);
  curve->setName(name);
  QPen pen(c);
  pen.setWidthF(width);
  if (s == plot::Style::kDashed) pen.setStyle(Qt::DashLine);
  curve->setPen(pen);
  return curve;
}

QCPGraph* addMarks(QCustomPlot* p, const QString& name, const QColor& c,
                   QCPScatterStyle::ScatterShape shape, double size) {
  QCPGraph* g = p->addGraph();
  g->setName(name);
  g->setLineStyle(QCPGraph::lsNone);
  const QPen pen(c);  // 1 px: wider marker pens go through Qt's stroker, hundreds of times a replot
  g->setPen(pen);
  g->setScatterStyle(QCPScatterStyle(shape, pen, Qt::NoBrush, size));
  return g;
}

class UnderwaterView final : public ScenarioView {
 public:
  QList<PlotPanel> createPlots(QWidget* parent) override {
    using namespace plot;
    track_ = makePlot(parent, "Top view: command, true and estimated track; beacons", "y east (m)",
                      "x north (m)");
    // The command is drawn last, in its own colour: it runs close to the truth and the estimate
    // and would vanish under either. Solid: a dashed pen over its thousands of vertices (14 turns
    // of the helix) costs several milliseconds a replot.
    track_true_ = addCurve(track_, "true", color::kTruth, Style::kLine);
    track_est_ = addCurve(track_, "estimate", color::kEstimate, Style::kLine);
    track_cmd_ = addCurve(track_, "command", color::kFourth, Style::kLine);
    beacons_ =
        addCurve(track_, "beacons (at the edge\nwhen out of view)", color::kSecond, Style::kLine);
    beacons_->setLineStyle(QCPCurve::lsNone);
    beacons_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssDiamond, QPen(color::kSecond, 2),
                                              QBrush(color::kSecond), 10));
    for (int b = 0; b < underwater::kBeacons; ++b) {
      auto* label = new QCPItemText(track_);
      label->setFont(QFont(track_->font().family(), 8));
      label->setColor(color::kSecond);
      label->setPadding(QMargins(7, 6, 7, 6));
      beacon_labels_.push_back(label);
    }
    here_ = addMarks(track_, "estimate at cursor", color::kEstimate, QCPScatterStyle::ssCircle, 9);
    // The legend goes beside the axis rect: an equal-scale top view leaves spare width, and inside
    // it would cover the track or a beacon. A spacer row under it keeps the legend at its own
    // height, level with the top of the plot.
    auto* side = new QCPLayoutGrid;
    side->setMargins(QMargins(0, 6, 6, 6));
    side->addElement(0, 0, track_->legend);  // out of makePlot's legend row, which goes
    track_->plotLayout()->simplify();
    track_->plotLayout()->addElement(axisRectRow(track_), 1, side);
    track_->plotLayout()->setColumnStretchFactor(1, 0.001);
    track_->legend->setWrap(1);
    side->addElement(1, 0, new QCPLayoutElement(track_));
    side->setRowStretchFactor(0, 0.001);
    // Equal scale on both axes at whatever size the plot is drawn (window, export): the ranges
    // follow the axis rect's pixel size after every layout.
    connect(track_, &QCustomPlot::afterLayout, this, [this] { fitTopView(); });
    for (QCPAxis* a : {track_->xAxis, track_->yAxis}) {
      connect(a, qOverload<const QCPRange&>(&QCPAxis::rangeChanged), this, [this] {
        if (!fitting_) userMovedTopView();
      });
    }

    err_ = makePlot(parent, "Distance error |estimate − truth| (Han et al. 2016, Fig. 3b)",
                    "time (s)", "distance error (m)");
    err_y_ = addGraph(err_, "distance error", color::kEstimate, Style::kLine);
    err_cursor_ = addCursor(err_);

    innov_ = makePlot(parent, "Range innovations with ± 2√S; gated samples marked", "time (s)",
                      "innovation z − ẑ (m)");
    innov_band_ = addBand(innov_, "± 2√S", color::kSecond);
    innov_used_ = addGraph(innov_, "accepted", color::kEstimate, Style::kDots);
    innov_rejected_ =
        addMarks(innov_, "rejected by the χ² gate", color::kSecond, QCPScatterStyle::ssCross, 6);
    innov_injected_ =
        addMarks(innov_, "injected outlier", color::kTruth, QCPScatterStyle::ssCircle, 8);
    innov_cursor_ = addCursor(innov_);

    raster_ =
        makePlot(parent, "Sensor timing: sampled, rejected, invalid, missing", "time (s)", "");
    QSharedPointer<QCPAxisTickerText> ticks(new QCPAxisTickerText);
    for (int s = 0; s < underwater::kSensorCount; ++s) {
      ticks->addTick(s, QString::fromLatin1(underwater::sensor_name(s)));
    }
    raster_->yAxis->setTicker(ticks);
    raster_->yAxis->setRangeReversed(true);
    raster_used_ = addGraph(raster_, "sampled", color::kSensor, Style::kDots);
    raster_rejected_ =
        addMarks(raster_, "rejected (gate)", color::kSecond, QCPScatterStyle::ssCross, 6);
    raster_invalid_ =
        addMarks(raster_, "invalid (≤ 0, S ≤ 0)", color::kFifth, QCPScatterStyle::ssTriangle, 6);
    raster_missing_ =
        addMarks(raster_, "missing", color::kFourth, QCPScatterStyle::ssTriangleInverted, 6);
    raster_cursor_ = addCursor(raster_);

    cov_ = makePlot(parent, "Covariance of simulated errors (left) vs design (right)", "", "");
    cov_title_ = qobject_cast<QCPTextElement*>(cov_->plotLayout()->element(0, 0));
    cov_->legend->setVisible(false);
    cov_->setInteractions(QCP::Interactions());
    cov_sim_ = new QCPColorMap(cov_->xAxis, cov_->yAxis);
    cov_design_ = new QCPColorMap(cov_->xAxis, cov_->yAxis);
    cov_sim_->setName("simulated");
    cov_design_->setName("design");
    for (QCPColorMap* m : {cov_sim_, cov_design_}) {
      m->data()->setSize(underwater::kErrorDims, underwater::kErrorDims);
      m->setInterpolate(false);
    }
    cov_sim_->data()->setRange(QCPRange(0, 4), QCPRange(0, 4));
    cov_design_->data()->setRange(QCPRange(6, 10), QCPRange(0, 4));
    auto* scale = new QCPColorScale(cov_);
    cov_scale_ = scale;
    cov_->plotLayout()->addElement(axisRectRow(cov_), 1, scale);
    QCPColorGradient g;
    g.setColorStopAt(0.0, QColor(33, 102, 172));
    g.setColorStopAt(0.5, QColor(247, 247, 247));
    g.setColorStopAt(1.0, QColor(178, 24, 43));
    for (QCPColorMap* m : {cov_sim_, cov_design_}) {
      m->setColorScale(scale);
      m->setGradient(g);
    }
    QSharedPointer<QCPAxisTickerText> cx(new QCPAxisTickerText), cy(new QCPAxisTickerText);
    const char* short_names[] = {"r1", "r2", "r3", "r4", "depth"};
    for (int i = 0; i < underwater::kErrorDims; ++i) {
      cx->addTick(i, short_names[i]);
      cx->addTick(6 + i, short_names[i]);
      cy->addTick(i, short_names[i]);
    }
    cov_->xAxis->setTicker(cx);
    cov_->yAxis->setTicker(cy);
    cov_->xAxis->setRange(-0.6, 10.6);
    cov_->yAxis->setRange(-0.6, 4.6);
    cov_->yAxis->setRangeReversed(true);
    // No grid: its lines would run through the gap between the two matrices.
    for (QCPAxis* a : {cov_->xAxis, cov_->yAxis}) {
      a->grid()->setVisible(false);
      a->grid()->setZeroLinePen(Qt::NoPen);
      a->setTicks(true);
      a->setSubTicks(false);
    }
    for (int k = 0; k < 2 * underwater::kErrorDims * underwater::kErrorDims; ++k) {
      auto* t = new QCPItemText(cov_);
      t->setFont(QFont(cov_->font().family(), 9));
      t->position->setType(QCPItemPosition::ptPlotCoords);
      cov_texts_.push_back(t);
    }
    cov_note_ = new QCPItemText(cov_);
    cov_note_->position->setType(QCPItemPosition::ptAxisRectRatio);
    cov_note_->position->setCoords(0.5, 0.5);
    cov_note_->setFont(QFont(cov_->font().family(), 8));
    cov_note_->setBrush(QBrush(QColor(255, 255, 255, 220)));

    return {{"trajectory", "Trajectory", track_},
            {"distance_error", "Distance error", err_},
            {"innovation", "Range innovations", innov_},
            {"timing", "Sensor timing", raster_},
            {"covariance", "Error covariance", cov_}};
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    Q_UNUSED(values);
    auto r = std::dynamic_pointer_cast<const UnderwaterResult>(result);
    if (!r) return;
    result_ = r;
    const std::size_t n = r->steps();
    // One ±2√S band over all four beacons: each range row contributes its own S.
    two_sqrt_S_.assign(n, kNoSample);
    zero_.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      for (const auto& S : r->S) {
        if (std::isfinite(S[k]) && S[k] > 0.0) {
          two_sqrt_S_[k] = 2.0 * std::sqrt(S[k]);
          break;
        }
      }
    }
    resetTopView(*r);
    drawCovariance(*r);
    drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

  // Ghosts: each snapshot's estimated track and distance error as faded lines.
  void setSnapshots(const Snapshots& snapshots) override {
    for (const Ghost& g : ghosts_)
      plot::removePlottables({g.track, g.err});
    ghosts_.clear();
    int i = 0;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const UnderwaterResult>(result);
      if (!r) continue;
      const int c = i++;
      const QString pinned = " [pinned: " + name + "]";
      ghosts_.push_back(
          {r, addCurve(track_, "estimate" + pinned, plot::color::ghost(c), plot::Style::kDashed),
           plot::addGhost(err_, "error" + pinned, c)});
    }
    if (result_) {
      drawUpTo(cursor_);
    } else {
      plot::replot(track_);
      plot::replot(err_);
    }
  }

 private:
  // Dark text on light cells, white on dark ones (the cell colour from the map's gradient).
  QColor textColorOn(double v, double vmax) const {
    const QColor cell =
        QColor::fromRgb(cov_sim_->gradient().color(v, QCPRange(-vmax, vmax), false));
    const double luma = 0.299 * cell.red() + 0.587 * cell.green() + 0.114 * cell.blue();
    return luma < 150.0 ? QColor(255, 255, 255) : QColor(20, 20, 20);
  }

  // Covariances are shown in the unit that keeps a cell's number short (3–4 digits): cm² for
  // decimetre-level errors (seed 004: 0.01 m² = 100 cm²), m² or mm² for much larger or smaller.
  void drawCovariance(const UnderwaterResult& r) {
    using underwater::kErrorDims;
    double vmax = 1e-12;
    for (int i = 0; i < kErrorDims; ++i) {
      for (int j = 0; j < kErrorDims; ++j) {
        vmax = std::max({vmax, std::abs(r.design(i, j)),
                         r.has_stats ? std::abs(r.stats.covariance(i, j)) : 0.0});
      }
    }
    // Not a structured binding: clang 14 cannot capture one in a lambda (number, below).
    const std::pair<double, QString> su = vmax >= 1.0    ? std::pair{1.0, QString("m²")}
                                          : vmax >= 1e-4 ? std::pair{1e4, QString("cm²")}
                                                         : std::pair{1e6, QString("mm²")};
    const double scale = su.first;
    const QString& unit = su.second;
    const double top = vmax * scale;
    const int decimals = top >= 100.0 ? 0 : top >= 10.0 ? 1 : 2;
    auto number = [&](double v) {
      const QString text = QString::number(v * scale, 'f', decimals);
      return text.startsWith('-') && text.toDouble() == 0.0 ? text.mid(1) : text;  // no "-0"
    };
    std::size_t k = 0;
    for (int i = 0; i < kErrorDims; ++i) {
      for (int j = 0; j < kErrorDims; ++j) {
        const double sim = r.has_stats ? r.stats.covariance(i, j) : 0.0;
        cov_sim_->data()->setCell(j, i, sim * scale);
        cov_design_->data()->setCell(j, i, r.design(i, j) * scale);
        cov_texts_[k]->position->setCoords(j, i);
        cov_texts_[k]->setText(r.has_stats ? number(sim) : QString());
        cov_texts_[k]->setColor(textColorOn(sim, vmax));
        cov_texts_[k + 1]->position->setCoords(6 + j, i);
        cov_texts_[k + 1]->setText(number(r.design(i, j)));
        cov_texts_[k + 1]->setColor(textColorOn(r.design(i, j), vmax));
        k += 2;
      }
    }
    cov_sim_->setDataRange(QCPRange(-top, top));
    cov_design_->setDataRange(QCPRange(-top, top));
    cov_scale_->setLabel("covariance (" + unit + ")");
    if (cov_title_) {
      cov_title_->setText("Covariance of simulated errors (left) vs design (right), " + unit);
    }
    cov_note_->setVisible(!r.has_stats);
    cov_note_->setText(
        "no truth columns: the simulated-error covariance needs x_true, y_true, z_true");
    cov_->xAxis->setLabel(r.has_stats ? QString("%1 synchronous instants; %2 with an injected "
                                                "outlier left out")
                                            .arg(r.stats.instants)
                                            .arg(r.stats.outlier_instants)
                                      : QString());
    plot::replot(cov_);
  }

  void drawUpTo(std::size_t index) {
    const UnderwaterResult& r = *result_;
    const std::size_t steps = r.steps();
    const bool all = index >= steps;
    const std::size_t n = all ? steps : index + 1;
    const double t0 = steps ? r.t.front() : 0.0, t1 = steps ? r.t.back() : 1.0;
    const double tc = steps ? r.t[std::min(n, steps) - 1] : 0.0;

    // Trajectory.
    // The top view puts east to the right and north up: key = y, value = x.
    plot::setCurve(track_cmd_, r.y_cmd, r.x_cmd, n);
    plot::setCurve(track_true_, r.y_true, r.x_true, n);
    plot::setCurve(track_est_, r.y, r.x, n);
    here_->data()->clear();
    if (n > 0 && std::isfinite(r.x[n - 1])) here_->addData(r.y[n - 1], r.x[n - 1]);

    // Distance error.
    plot::setSeries(err_y_, r.t, r.pos_err, n);

    // Ghosts, cut at the cursor's time (a snapshot keeps its own time base).
    for (const Ghost& g : ghosts_) {
      const auto& gt = g.result->t;
      const std::size_t m =
          all ? gt.size()
              : static_cast<std::size_t>(std::upper_bound(gt.begin(), gt.end(), tc) - gt.begin());
      plot::setCurve(g.track, g.result->y, g.result->x, m);
      plot::setSeries(g.err, gt, g.result->pos_err, m);
    }

    // Innovations: accepted, rejected, injected (over every beacon).
    std::vector<double> used_t, used_y;
    QVector<QCPGraphData> rejected, injected;
    const auto kRange = static_cast<std::size_t>(underwater::kRange1);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t b = 0; b < static_cast<std::size_t>(underwater::kBeacons); ++b) {
        const double y = r.innovation[b][k];
        if (!std::isfinite(y)) continue;
        if (r.status[kRange + b][k] == underwater::kRejected) {
          rejected.append(QCPGraphData(r.t[k], y));
        } else {
          used_t.push_back(r.t[k]);
          used_y.push_back(y);
        }
        const double inj = r.injected[b][k];
        if (std::isfinite(inj) && inj != 0.0) injected.append(QCPGraphData(r.t[k], y));
      }
    }
    plot::setDots(innov_used_, used_t, used_y);
    innov_rejected_->data()->set(rejected, true);
    innov_injected_->data()->set(injected, true);
    plot::setBand(innov_band_, r.t, zero_, two_sqrt_S_, n);

    // Timing raster.
    std::vector<double> sampled_t, sampled_row;
    QVector<QCPGraphData> rej, inval, miss;
    for (int s = 0; s < underwater::kSensorCount; ++s) {
      const auto& st = r.status[static_cast<std::size_t>(s)];
      for (std::size_t k = 0; k < n; ++k) {
        if (std::isnan(st[k])) continue;
        if (st[k] == underwater::kRejected) {
          rej.append(QCPGraphData(r.t[k], s));
        } else if (st[k] == underwater::kInvalid) {
          inval.append(QCPGraphData(r.t[k], s));
        } else {
          sampled_t.push_back(r.t[k]);
          sampled_row.push_back(s);
        }
      }
      for (double tm : r.missing_t[static_cast<std::size_t>(s)]) {
        if (tm <= tc || all) miss.append(QCPGraphData(tm, s));
      }
    }
    plot::setDots(raster_used_, sampled_t, sampled_row);
    raster_rejected_->data()->set(rej, false);
    raster_invalid_->data()->set(inval, false);
    raster_missing_->data()->set(miss, false);

    plot::rescale(err_, t0, t1);
    plot::rescale(innov_, t0, t1);
    rescaleInnovations(r);
    raster_->xAxis->setRange(t0, t1);
    raster_->yAxis->setRange(-0.7, static_cast<int>(underwater::kSensorCount) - 0.3);
    for (auto* c : {err_cursor_, innov_cursor_, raster_cursor_})
      plot::setCursorAt(c, tc, !all);
    for (QCustomPlot* p : {track_, err_, innov_, raster_})
      plot::replot(p);
  }

  // Symmetric range holding the band and every innovation, but no more than 3 m: one wild sample
  // must not squash the plot.
  void rescaleInnovations(const UnderwaterResult& r) {
    double big = 0.0;
    for (double s : two_sqrt_S_) {
      if (std::isfinite(s)) big = std::max(big, s);
    }
    for (const auto& in : r.innovation) {
      for (double y : in) {
        if (std::isfinite(y)) big = std::max(big, std::min(std::abs(y), 3.0));
      }
    }
    if (big > 0.0) innov_->yAxis->setRange(-1.1 * big, 1.1 * big);
  }

  // The box the top view must show: every track of the run with a small margin (beacons are
  // usually far outside; they are drawn at the edge).
  void resetTopView(const UnderwaterResult& r) {
    double lo_e = 1e300, hi_e = -1e300, lo_n = 1e300, hi_n = -1e300;
    auto grow = [&](const std::vector<double>& north, const std::vector<double>& east) {
      for (std::size_t i = 0; i < std::min(north.size(), east.size()); ++i) {
        if (!std::isfinite(north[i]) || !std::isfinite(east[i])) continue;
        lo_n = std::min(lo_n, north[i]);
        hi_n = std::max(hi_n, north[i]);
        lo_e = std::min(lo_e, east[i]);
        hi_e = std::max(hi_e, east[i]);
      }
    };
    grow(r.x_true, r.y_true);
    grow(r.x, r.y);
    grow(r.x_cmd, r.y_cmd);
    if (lo_n > hi_n) lo_n = hi_n = lo_e = hi_e = 0.0;
    view_east_ = 0.5 * (lo_e + hi_e);
    view_north_ = 0.5 * (lo_n + hi_n);
    view_half_east_ = std::max(0.53 * (hi_e - lo_e), 0.5);
    view_half_north_ = std::max(0.53 * (hi_n - lo_n), 0.5);
  }

  // Pixels kept clear along each edge of the top view for the beacon markers and their labels.
  static double edgeBand(int w, int h) { return std::min({40.0, 0.25 * w, 0.25 * h}); }

  // A drag or zoom by the user moves the box the view keeps.
  void userMovedTopView() {
    const QCPAxisRect* ar = track_->axisRect();
    const int w = ar->width(), h = ar->height();
    if (w <= 0 || h <= 0) return;
    const double band = edgeBand(w, h);
    const QCPRange x = track_->xAxis->range(), y = track_->yAxis->range();
    view_east_ = x.center();
    view_north_ = y.center();
    view_half_east_ = 0.5 * x.size() * (w - 2.0 * band) / w;
    view_half_north_ = 0.5 * y.size() * (h - 2.0 * band) / h;
  }

  // Equal scale: one metre is as many pixels east as north. Runs after every layout (screen
  // replot and export alike): fits the box inside the axis rect less the edge band, widens the
  // roomier axis, lays the plot out again (the tick labels may change the margins) and places
  // the beacons for this size.
  void fitTopView() {
    if (fitting_) return;
    fitting_ = true;
    QCPAxisRect* ar = track_->axisRect();
    for (int pass = 0; pass < 3; ++pass) {
      const int w = ar->width(), h = ar->height();
      if (w <= 0 || h <= 0) break;
      const double band = edgeBand(w, h);
      const double m_per_px = std::max(2.0 * view_half_east_ / (w - 2.0 * band),
                                       2.0 * view_half_north_ / (h - 2.0 * band));
      track_->xAxis->setRange(view_east_ - 0.5 * w * m_per_px, view_east_ + 0.5 * w * m_per_px);
      track_->yAxis->setRange(view_north_ - 0.5 * h * m_per_px, view_north_ + 0.5 * h * m_per_px);
      for (auto phase : {QCPLayoutElement::upPreparation, QCPLayoutElement::upMargins,
                         QCPLayoutElement::upLayout}) {
        track_->plotLayout()->update(phase);
      }
      if (ar->width() == w && ar->height() == h) break;
    }
    placeBeacons();
    fitting_ = false;
  }

  // Beacons in view sit where they are; the others are drawn at the edge along their bearing from
  // the centre of the view. A label is centred over or under its marker, on the inner side, and
  // moved sideways as far as it must to stay inside.
  void placeBeacons() {
    const QRect rect = track_->axisRect()->rect();
    if (rect.width() <= 0 || rect.height() <= 0) return;
    constexpr double kInset = 12.0;  // px: half a marker and a little air
    const double cx = 0.5 * (rect.left() + rect.right()), cy = 0.5 * (rect.top() + rect.bottom());
    const double half_w = 0.5 * rect.width() - kInset, half_h = 0.5 * rect.height() - kInset;
    QVector<QCPCurveData> d;
    for (int b = 0; b < underwater::kBeacons; ++b) {
      const auto& B = underwater::beacons()[static_cast<std::size_t>(b)];
      double dx = track_->xAxis->coordToPixel(B(1)) - cx;
      double dy = track_->yAxis->coordToPixel(B(0)) - cy;
      const double over = std::max({std::abs(dx) / half_w, std::abs(dy) / half_h, 1.0});
      dx /= over;
      dy /= over;
      const double px = cx + dx, py = cy + dy;
      d.append(QCPCurveData(b, track_->xAxis->pixelToCoord(px), track_->yAxis->pixelToCoord(py)));
      auto* label = beacon_labels_[static_cast<std::size_t>(b)];
      label->setText(QString("B%1 (%2, %3, %4)").arg(b + 1).arg(B(0)).arg(B(1)).arg(B(2)));
      const QMargins pad = label->padding();
      const double half_text = 0.5 * (QFontMetrics(label->font()).horizontalAdvance(label->text()) +
                                      pad.left() + pad.right());
      const double lo = rect.left() + 2.0 + half_text, hi = rect.right() - 2.0 - half_text;
      const double lx = lo < hi ? std::clamp(px, lo, hi) : cx;
      label->setPositionAlignment(Qt::AlignHCenter | (dy <= 0 ? Qt::AlignTop : Qt::AlignBottom));
      label->position->setCoords(track_->xAxis->pixelToCoord(lx), track_->yAxis->pixelToCoord(py));
    }
    beacons_->data()->set(d, true);
  }

  struct Ghost {
    std::shared_ptr<const UnderwaterResult> result;
    QCPCurve* track = nullptr;
    QCPGraph* err = nullptr;
  };

  std::shared_ptr<const UnderwaterResult> result_;
  std::size_t cursor_ = plot::kAll;
  std::vector<double> two_sqrt_S_, zero_;
  std::vector<Ghost> ghosts_;
  // The box the top view keeps in sight (centre and half extents, m); fitTopView widens one side
  // to the axis rect's aspect.
  double view_east_ = 0.0, view_north_ = 0.0, view_half_east_ = 1.0, view_half_north_ = 1.0;
  bool fitting_ = false;

  QCustomPlot *track_ = nullptr, *err_ = nullptr, *innov_ = nullptr, *raster_ = nullptr,
              *cov_ = nullptr;
  QCPCurve *track_cmd_ = nullptr, *track_true_ = nullptr, *track_est_ = nullptr,
           *beacons_ = nullptr;
  std::vector<QCPItemText*> beacon_labels_;
  QCPGraph* here_ = nullptr;
  QCPGraph* err_y_ = nullptr;
  plot::Band innov_band_;
  QCPGraph *innov_used_ = nullptr, *innov_rejected_ = nullptr, *innov_injected_ = nullptr;
  QCPGraph *raster_used_ = nullptr, *raster_rejected_ = nullptr, *raster_invalid_ = nullptr,
           *raster_missing_ = nullptr;
  QCPColorMap *cov_sim_ = nullptr, *cov_design_ = nullptr;
  QCPColorScale* cov_scale_ = nullptr;
  QCPTextElement* cov_title_ = nullptr;
  std::vector<QCPItemText*> cov_texts_;
  QCPItemText* cov_note_ = nullptr;
  QCPItemStraightLine *err_cursor_ = nullptr, *innov_cursor_ = nullptr, *raster_cursor_ = nullptr;
};

}  // namespace

void register_view_underwater(ViewRegistry& registry) {
  registry.add("underwater", [] { return std::make_unique<UnderwaterView>(); });
}

}  // namespace kfw
