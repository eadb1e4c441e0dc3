// Plots of the `radome` scenario (seed 001): slope estimates vs truth with the grid envelope
// (Figs. 3, 5, 7, 9), spatial refraction error (Figs. 4, 6, 8), LOS angles, IMM mode probabilities
// (heat map at the replay cursor and the top modes over time), innovations and NIS; plus the IMM
// grid editor (min / max / n per axis, stay probability, Kp, the grid's slope values).
#include <qcustomplot.h>

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QLabel>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "core/statistics.h"
#include "plot_blocks.h"
#include "plot_kit.h"
#include "scenario_view.h"
#include "scenarios/radome/radome_imm.h"

namespace kfw {

namespace {

using radome::RadomeResult;

constexpr int kTopModes = 5;
constexpr double kLogMuFloor = -8.0;         // heat map shows log10 μ from 1e-8 to 1
constexpr std::size_t kMaxTickedSlopes = 9;  // up to this many grid values: a tick at each

// Ticks at the grid's slope values (3 decimals) for a small grid, the normal ticker otherwise.
void setGridTicks(QCPAxis* axis, const std::vector<double>& grid,
                  const QSharedPointer<QCPAxisTickerText>& text,
                  const QSharedPointer<QCPAxisTicker>& normal) {
  if (grid.size() > kMaxTickedSlopes) {
    if (axis->ticker() != normal) axis->setTicker(normal);
    return;
  }
  text->clear();
  for (double x : grid) {
    QString label = QString::number(x, 'f', 3);
    if (label == "-0.000") label = "0.000";
    text->addTick(x, label);
  }
  if (axis->ticker() != text) axis->setTicker(text);
}

// The IMM grid editor: one spin box per grid key, and the grid's slope values.
class ImmGridEditor final : public QGroupBox {
 public:
  ImmGridEditor(ScenarioView* view, QWidget* parent)
      : QGroupBox("IMM grid (Kim & Back 2017, eqs. 4, 6)", parent) {
    setObjectName("radome.gridEditor");
    auto sc = make_scenario("radome");
    auto* form = new QFormLayout;
    auto add_double = [&](const char* key, const QString& label, int decimals, double step) {
      auto* s = new QDoubleSpinBox(this);
      s->setObjectName(QString("radome.") + key);
      s->setDecimals(decimals);
      s->setSingleStep(step);
      if (sc.ok()) {
        if (const ParamSpec* spec = (*sc)->params().find(key)) s->setRange(spec->min, spec->max);
      }
      form->addRow(label, s);
      connect(s, &QDoubleSpinBox::valueChanged, this,
              [view, key](double v) { emit view->parameterEdited(key, v); });
      return s;
    };
    auto add_int = [&](const char* key, const QString& label) {
      auto* s = new QSpinBox(this);
      s->setObjectName(QString("radome.") + key);
      if (sc.ok()) {
        if (const ParamSpec* spec = (*sc)->params().find(key)) {
          s->setRange(static_cast<int>(spec->min), static_cast<int>(spec->max));
        }
      }
      form->addRow(label, s);
      connect(s, &QSpinBox::valueChanged, this,
              [view, key](int v) { emit view->parameterEdited(key, static_cast<double>(v)); });
      return s;
    };
    min_ = add_double("grid.min", "min R̄ (both axes)", 3, 0.005);
    max_ = add_double("grid.max", "max R̄ (both axes)", 3, 0.005);
    n_psi_ = add_int("grid.n_psi", "n_ψ (azimuth)");
    n_theta_ = add_int("grid.n_theta", "n_θ (elevation)");
    stay_ = add_double("markov.stay", "Markov stay p^jj", 4, 0.005);
    kp_ = add_double("Kp", "renewal gain Kp", 3, 0.05);
    values_ = new QLabel(this);
    values_->setObjectName("radome.gridValues");
    values_->setTextFormat(Qt::RichText);
    values_->setWordWrap(true);
    auto* box = new QVBoxLayout(this);
    box->addLayout(form);
    box->addWidget(values_);
  }

  // Shows the parameters a run used, without re-emitting them.
  void setValues(const ParamValues& v) {
    auto set = [&](auto* w, const char* key) {
      const auto it = v.find(key);
      if (it == v.end()) return;
      const QSignalBlocker block(w);
      if constexpr (std::is_same_v<std::remove_pointer_t<decltype(w)>, QSpinBox>) {
        w->setValue(static_cast<int>(it->second));
      } else {
        w->setValue(it->second);
      }
    };
    set(min_, "grid.min");
    set(max_, "grid.max");
    set(n_psi_, "grid.n_psi");
    set(n_theta_, "grid.n_theta");
    set(stay_, "markov.stay");
    set(kp_, "Kp");
  }

  // The grid of slope values at a replay step (it moves when Kp > 0).
  void showGrid(const RadomeResult& r, std::size_t k, double t_s) {
    auto row = [](const std::vector<double>& g) {
      QStringList s;
      for (double x : g)
        s << QString::number(x, 'f', 4);
      return s.join("  ");
    };
    values_->setText(
        QString("<b>grid at t = %1 s</b> (%2 modes)<br><tt>R̄_ψ: %3</tt><br><tt>R̄_θ: %4</tt>")
            .arg(t_s, 0, 'f', 2)
            .arg(r.modes())
            .arg(row(r.grid_psi(k)))
            .arg(row(r.grid_theta(k))));
  }

 private:
  QDoubleSpinBox *min_ = nullptr, *max_ = nullptr, *stay_ = nullptr, *kp_ = nullptr;
  QSpinBox *n_psi_ = nullptr, *n_theta_ = nullptr;
  QLabel* values_ = nullptr;
};

class RadomeView final : public ScenarioView {
 public:
  QWidget* createControls(QWidget* parent) override {
    editor_ = new ImmGridEditor(this, parent);
    return editor_;
  }

  QList<PlotPanel> createPlots(QWidget* parent) override {
    using namespace plot;
    for (int axis = 0; axis < 2; ++axis) {
      const QString sym = axis == 0 ? "ψ" : "θ";
      SlopePlot& s = slope_[axis];
      s.plot =
          makePlot(parent, QString("Slope R_%1 and its grid (Kim & Back 2017, Figs. 3–9)").arg(sym),
                   "time (s)", QString("slope R_%1 (–)").arg(sym));
      s.envelope = addBand(s.plot, "grid envelope", color::kSensor);
      s.center = addGraph(s.plot, "grid centre", color::kBound, Style::kDashed);
      s.truth = addGraph(s.plot, "truth", color::kTruth);
      s.est = addGraph(s.plot, QString("estimate Σ μ^j R̄_%1^j").arg(sym), color::kEstimate);
      s.cursor = addCursor(s.plot);
    }
    alpha_ = makePlot(parent, "Spatial refraction error α (Kim & Back 2017, Figs. 4, 6, 8)",
                      "time (s)", "α (deg)");
    alpha_meas_ = addGraph(alpha_, "measured (vs true LOS)", color::kSensor, Style::kDots);
    alpha_true_ = addGraph(alpha_, "true", color::kTruth);
    alpha_est_ = addGraph(alpha_, "estimated", color::kEstimate);
    alpha_cursor_ = addCursor(alpha_);

    los_ = makePlot(parent, "LOS angle error against the true LOS: measured and estimated",
                    "time (s)", "LOS angle − true LOS (deg)");
    los_psi_ = addGraph(los_, "measured z_ψ − ψ_LOS", color::kEstimate, Style::kDots);
    los_theta_ = addGraph(los_, "measured z_θ − θ_LOS", color::kSecond, Style::kDots);
    los_est_psi_ = addGraph(los_, "estimated ψ_LOS − ψ_LOS", color::kThird);
    los_est_theta_ = addGraph(los_, "estimated θ_LOS − θ_LOS", color::kFourth);
    los_cursor_ = addCursor(los_);

    heat_ = makePlot(parent, "Mode probabilities μ on the slope grid at the replay cursor",
                     "slope R̄_ψ (–)", "slope R̄_θ (–)");
    heat_->legend->setVisible(false);
    for (int axis = 0; axis < 2; ++axis) {
      heat_text_ticker_[axis].reset(new QCPAxisTickerText);
      heat_text_ticker_[axis]->setSubTickCount(0);
      heat_normal_ticker_[axis].reset(new QCPAxisTicker);
    }
    heat_map_ = new QCPColorMap(heat_->xAxis, heat_->yAxis);
    heat_scale_ = new QCPColorScale(heat_);
    // Beside the axis rect (below the title row that makePlot adds).
    QCPLayoutGrid* layout = heat_->plotLayout();
    int rect_row = 0;
    for (int row = 0; row < layout->rowCount(); ++row) {
      if (layout->element(row, 0) == heat_->axisRect()) rect_row = row;
    }
    layout->addElement(rect_row, 1, heat_scale_);
    heat_scale_->setType(QCPAxis::atRight);
    heat_scale_->axis()->setLabel("log₁₀ μ (–)");
    auto* margins = new QCPMarginGroup(heat_);
    heat_->axisRect()->setMarginGroup(QCP::msBottom | QCP::msTop, margins);
    heat_scale_->setMarginGroup(QCP::msBottom | QCP::msTop, margins);
    heat_map_->setColorScale(heat_scale_);
    heat_map_->setGradient(QCPColorGradient(QCPColorGradient::gpThermal));
    heat_map_->setInterpolate(false);
    heat_map_->setDataRange(QCPRange(kLogMuFloor, 0.0));
    heat_label_ = new QCPItemText(heat_);
    heat_label_->position->setType(QCPItemPosition::ptAxisRectRatio);
    heat_label_->position->setCoords(0.02, 0.03);
    heat_label_->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
    heat_label_->setBrush(QBrush(QColor(255, 255, 255, 210)));
    heat_label_->setPadding(QMargins(4, 2, 4, 2));

    top_ = makePlot(parent, "Mode probabilities over time: the top modes", "time (s)", "μ (–)");
    for (int i = 0; i < kTopModes; ++i)
      top_graphs_.push_back(addGraph(top_, "", color::cycle(i)));
    top_cursor_ = addCursor(top_);
    // Probability ticks only.
    QSharedPointer<QCPAxisTickerText> mu_ticks(new QCPAxisTickerText);
    for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
      mu_ticks->addTick(v, QString::number(v));
    mu_ticks->setSubTickCount(4);
    top_->yAxis->setTicker(mu_ticks);

    innov_ = makePlot(parent, "Innovations of the most probable mode with ± 2√S", "time (s)",
                      "innovation (m)");
    const QColor axis_color[3] = {color::kEstimate, color::kSecond, color::kThird};
    const char* axis_name[3] = {"x", "y", "z"};
    for (int ax = 0; ax < 3; ++ax) {
      QColor c = axis_color[ax];
      innov_band_[ax] = addBand(innov_, QString("± 2√S_%1").arg(axis_name[ax]), c, true);
      // The three bands overlap: each edge in its colour and dash tells them apart there.
      const Qt::PenStyle edge[3] = {Qt::SolidLine, Qt::DashLine, Qt::DotLine};
      plot::outlineBand(innov_band_[ax], edge[ax]);
      innov_y_[ax] = addGraph(innov_, QString("innovation %1").arg(axis_name[ax]), c, Style::kDots);
    }
    innov_cursor_ = addCursor(innov_);

    nis_ = std::make_unique<NisPlot>(parent, "NIS of the most probable mode, 95 % χ²(3) bounds");

    return {{"slope_psi", "Slope R_ψ", slope_[0].plot},
            {"slope_theta", "Slope R_θ", slope_[1].plot},
            {"refraction_error", "Refraction error α", alpha_},
            {"los", "LOS error", los_},
            {"mode_heatmap", "Mode probabilities (grid)", heat_},
            {"mode_top", "Top modes", top_},
            {"innovation", "Innovation", innov_},
            {"nis", "NIS", nis_->plot()}};
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    auto r = std::dynamic_pointer_cast<const RadomeResult>(result);
    if (!r) return;
    result_ = r;
    if (editor_) editor_->setValues(values);
    const std::size_t n = r->steps();
    const double op_lo = r->offsets_psi.front(), op_hi = r->offsets_psi.back();
    const double ot_lo = r->offsets_theta.front(), ot_hi = r->offsets_theta.back();
    for (int axis = 0; axis < 2; ++axis) {
      auto& lo = env_lo_[axis];
      auto& hi = env_hi_[axis];
      const auto& c = axis == 0 ? r->center_psi : r->center_theta;
      lo.resize(n);
      hi.resize(n);
      for (std::size_t k = 0; k < n; ++k) {
        lo[k] = c[k] + (axis == 0 ? op_lo : ot_lo);
        hi[k] = c[k] + (axis == 0 ? op_hi : ot_hi);
      }
    }
    los_err_[0].assign(n, kNoSample);
    los_err_[1].assign(n, kNoSample);
    los_est_err_[0].assign(n, kNoSample);
    los_est_err_[1].assign(n, kNoSample);
    for (std::size_t k = 0; k < n; ++k) {
      los_err_[0][k] = r->psi_meas_deg[k] - r->psi_los_true_deg[k];
      los_err_[1][k] = r->theta_meas_deg[k] - r->theta_los_true_deg[k];
      los_est_err_[0][k] = r->psi_los_est_deg[k] - r->psi_los_true_deg[k];
      los_est_err_[1][k] = r->theta_los_est_deg[k] - r->theta_los_true_deg[k];
    }
    for (int ax = 0; ax < 3; ++ax) {
      two_sqrt_S_[ax].resize(n);
      for (std::size_t k = 0; k < n; ++k) {
        const double S = r->S[static_cast<std::size_t>(ax)][k];
        two_sqrt_S_[ax][k] = std::isfinite(S) ? 2.0 * std::sqrt(S) : kNoSample;
      }
    }
    zero_.assign(n, 0.0);
    // Top modes by mean probability: series of μ^j over time.
    top_ids_ = r->top_modes(kTopModes);
    top_mu_.assign(top_ids_.size(), std::vector<double>(n, kNoSample));
    const auto modes = static_cast<std::size_t>(r->modes());
    for (std::size_t i = 0; i < top_ids_.size(); ++i) {
      const auto j = static_cast<std::size_t>(top_ids_[i]);
      for (std::size_t k = 0; k < n && k * modes + j < r->mu.size(); ++k) {
        top_mu_[i][k] = r->mu[k * modes + j];
      }
    }
    for (std::size_t i = 0; i < top_graphs_.size(); ++i) {
      QCPGraph* g = top_graphs_[i];
      if (i < top_ids_.size()) {
        // Named by its slopes (drawUpTo: at the shown time), not by grid indices.
        g->setVisible(true);
        g->addToLegend();
      } else {
        g->data()->clear();
        g->setVisible(false);
        g->removeFromLegend();
      }
    }
    // With renewal (Kp > 0) the grid's centre moves: a mode's slopes depend on the time.
    grid_moves_ = false;
    for (const auto* c : {&r->center_psi, &r->center_theta}) {
      if (c->empty()) continue;
      const auto [lo, hi] = std::minmax_element(c->begin(), c->end());
      grid_moves_ = grid_moves_ || *hi > *lo;
    }
    heat_map_->data()->setSize(r->n_psi, r->n_theta);
    nis_->setData(&r->t, &r->nis, 3.0);
    drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

  // Ghosts: each pinned tuning's slope estimates and refraction-error estimate as faded lines.
  void setSnapshots(const Snapshots& snapshots) override {
    for (const auto& g : ghosts_)
      plot::removePlottables({g.slope[0], g.slope[1], g.alpha});
    ghosts_.clear();
    int i = 0;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const RadomeResult>(result);
      if (!r) continue;
      const int c = i++;
      const QString pinned = " [pinned: " + name + "]";
      ghosts_.push_back({r,
                         {plot::addGhost(slope_[0].plot, "estimate" + pinned, c),
                          plot::addGhost(slope_[1].plot, "estimate" + pinned, c)},
                         plot::addGhost(alpha_, "estimated" + pinned, c)});
    }
    if (result_) drawUpTo(cursor_);
  }

 private:
  struct SlopePlot {
    QCustomPlot* plot = nullptr;
    plot::Band envelope;
    QCPGraph *center = nullptr, *truth = nullptr, *est = nullptr;
    QCPItemStraightLine* cursor = nullptr;
  };

  void drawHeatMap(std::size_t k) {
    const RadomeResult& r = *result_;
    const auto mu = r.mode_probabilities(k);
    const auto gp = r.grid_psi(k), gt = r.grid_theta(k);
    if (mu.empty() || gp.empty() || gt.empty()) return;
    // Cells centred on the grid slopes; a one-value axis gets a cell of ±0.01.
    const double hp = gp.size() > 1 ? (gp.back() - gp.front()) / (2.0 * (gp.size() - 1)) : 0.01;
    const double ht = gt.size() > 1 ? (gt.back() - gt.front()) / (2.0 * (gt.size() - 1)) : 0.01;
    heat_map_->data()->setRange(
        QCPRange(gp.front(), gp.back() > gp.front() ? gp.back() : gp.front() + 1e-9),
        QCPRange(gt.front(), gt.back() > gt.front() ? gt.back() : gt.front() + 1e-9));
    double best = -1.0;
    int best_j = 0;
    for (int b = 0; b < r.n_theta; ++b) {
      for (int a = 0; a < r.n_psi; ++a) {
        const auto j = static_cast<std::size_t>(a + r.n_psi * b);
        heat_map_->data()->setCell(a, b, std::log10(std::max(mu[j], 1e-8)));
        if (mu[j] > best) {
          best = mu[j];
          best_j = static_cast<int>(j);
        }
      }
    }
    if (!plot::userZoomedX(heat_)) heat_->xAxis->setRange(gp.front() - hp, gp.back() + hp);
    if (!plot::userZoomedY(heat_)) heat_->yAxis->setRange(gt.front() - ht, gt.back() + ht);
    setGridTicks(heat_->xAxis, gp, heat_text_ticker_[0], heat_normal_ticker_[0]);
    setGridTicks(heat_->yAxis, gt, heat_text_ticker_[1], heat_normal_ticker_[1]);
    const double tp = k < r.slope_psi_true.size() ? r.slope_psi_true[k] : kNoSample;
    const double tt = k < r.slope_theta_true.size() ? r.slope_theta_true[k] : kNoSample;
    heat_label_->setText(
        QString("t = %1 s   max μ = %2 at (%3, %4)\nestimate (%5, %6)   truth (%7, %8)")
            .arg(r.t[k], 0, 'f', 2)
            .arg(best, 0, 'f', 3)
            .arg(gp[static_cast<std::size_t>(best_j % r.n_psi)], 0, 'f', 3)
            .arg(gt[static_cast<std::size_t>(best_j / r.n_psi)], 0, 'f', 3)
            .arg(r.slope_psi[k], 0, 'f', 3)
            .arg(r.slope_theta[k], 0, 'f', 3)
            .arg(tp, 0, 'f', 3)
            .arg(tt, 0, 'f', 3));
  }

  // A mode by the slopes it stands for at step k (the grid centre + its offsets); when the grid
  // moves (renewal), with the time they hold at.
  QString modeName(const RadomeResult& r, int j, std::size_t k) const {
    const auto gp = r.grid_psi(k), gt = r.grid_theta(k);
    const auto a = static_cast<std::size_t>(j % r.n_psi), b = static_cast<std::size_t>(j / r.n_psi);
    QString name = QString("μ of R̄_ψ = %1, R̄_θ = %2")
                       .arg(a < gp.size() ? gp[a] : kNoSample, 0, 'f', 3)
                       .arg(b < gt.size() ? gt[b] : kNoSample, 0, 'f', 3);
    if (grid_moves_ && k < r.t.size()) name += QString(" at t = %1 s").arg(r.t[k], 0, 'f', 1);
    return name;
  }

  void drawUpTo(std::size_t index) {
    const RadomeResult& r = *result_;
    const std::size_t steps = r.steps();
    if (steps == 0) return;
    const bool all = index >= steps;
    const std::size_t n = all ? steps : index + 1;
    const double t0 = r.t.front(), t1 = r.t.back();
    const double tc = r.t[n - 1];
    using plot::setSeries;
    for (int axis = 0; axis < 2; ++axis) {
      SlopePlot& s = slope_[axis];
      plot::setBandLimits(s.envelope, r.t, env_lo_[axis], env_hi_[axis], n);
      setSeries(s.center, r.t, axis == 0 ? r.center_psi : r.center_theta, n);
      setSeries(s.truth, r.t, axis == 0 ? r.slope_psi_true : r.slope_theta_true, n);
      setSeries(s.est, r.t, axis == 0 ? r.slope_psi : r.slope_theta, n);
    }
    for (const auto& g : ghosts_) {
      const RadomeResult& gr = *g.result;
      // Cut at the cursor's time (a ghost may come from another dataset's time base).
      const std::size_t gn =
          all ? gr.steps()
              : static_cast<std::size_t>(std::upper_bound(gr.t.begin(), gr.t.end(), tc) -
                                         gr.t.begin());
      setSeries(g.slope[0], gr.t, gr.slope_psi, gn);
      setSeries(g.slope[1], gr.t, gr.slope_theta, gn);
      setSeries(g.alpha, gr.t, gr.alpha_est_deg, gn);
    }
    setSeries(alpha_meas_, r.t, r.alpha_meas_deg, n);
    setSeries(alpha_true_, r.t, r.alpha_true_deg, n);
    setSeries(alpha_est_, r.t, r.alpha_est_deg, n);
    setSeries(los_psi_, r.t, los_err_[0], n);
    setSeries(los_theta_, r.t, los_err_[1], n);
    setSeries(los_est_psi_, r.t, los_est_err_[0], n);
    setSeries(los_est_theta_, r.t, los_est_err_[1], n);
    for (std::size_t i = 0; i < top_ids_.size() && i < top_graphs_.size(); ++i) {
      setSeries(top_graphs_[i], r.t, top_mu_[i], n);
      top_graphs_[i]->setName(modeName(r, top_ids_[i], n - 1));
    }
    for (int ax = 0; ax < 3; ++ax) {
      plot::setBand(innov_band_[ax], r.t, zero_, two_sqrt_S_[ax], n);
      setSeries(innov_y_[ax], r.t, r.innovation[static_cast<std::size_t>(ax)], n);
    }
    nis_->draw(plot::frameAt(r.t, index));
    drawHeatMap(n - 1);
    if (editor_) editor_->showGrid(r, n - 1, tc);

    QCustomPlot* timed[] = {slope_[0].plot, slope_[1].plot, alpha_, los_, top_, innov_};
    for (QCustomPlot* p : {slope_[0].plot, slope_[1].plot, top_})
      plot::rescale(p, t0, t1);
    // The filter's start-up (first pseudo-measurement, P0) would set these ranges and flatten the
    // steady part: scale them from the settled data on.
    for (QCustomPlot* p : {alpha_, los_, innov_})
      plot::rescale(p, t0, t1, plot::settleTime(t0, t1));
    if (!plot::userZoomedY(top_)) top_->yAxis->setRange(-0.03, 1.05);
    QCPItemStraightLine* cursors[] = {slope_[0].cursor, slope_[1].cursor, alpha_cursor_,
                                      los_cursor_,      top_cursor_,      innov_cursor_};
    for (auto* c : cursors)
      plot::setCursorAt(c, tc, !all);
    for (QCustomPlot* p : timed)
      plot::replot(p);
    plot::replot(heat_);
  }

  struct Ghost {
    std::shared_ptr<const RadomeResult> result;
    QCPGraph* slope[2];
    QCPGraph* alpha;
  };
  std::vector<Ghost> ghosts_;
  std::shared_ptr<const RadomeResult> result_;
  std::size_t cursor_ = plot::kAll;
  ImmGridEditor* editor_ = nullptr;

  SlopePlot slope_[2];
  std::vector<double> env_lo_[2], env_hi_[2], los_err_[2], los_est_err_[2], two_sqrt_S_[3], zero_;
  std::vector<int> top_ids_;
  bool grid_moves_ = false;
  std::vector<std::vector<double>> top_mu_;

  QCustomPlot *alpha_ = nullptr, *los_ = nullptr, *heat_ = nullptr, *top_ = nullptr,
              *innov_ = nullptr;
  std::unique_ptr<plot::NisPlot> nis_;
  QCPGraph *alpha_meas_ = nullptr, *alpha_true_ = nullptr, *alpha_est_ = nullptr;
  QCPGraph *los_psi_ = nullptr, *los_theta_ = nullptr, *los_est_psi_ = nullptr,
           *los_est_theta_ = nullptr;
  QCPColorMap* heat_map_ = nullptr;
  QSharedPointer<QCPAxisTickerText> heat_text_ticker_[2];  // [ψ, θ]
  QSharedPointer<QCPAxisTicker> heat_normal_ticker_[2];
  QCPColorScale* heat_scale_ = nullptr;
  QCPItemText* heat_label_ = nullptr;
  std::vector<QCPGraph*> top_graphs_;
  plot::Band innov_band_[3];
  QCPGraph* innov_y_[3] = {nullptr, nullptr, nullptr};
  QCPItemStraightLine *alpha_cursor_ = nullptr, *los_cursor_ = nullptr, *top_cursor_ = nullptr,
                      *innov_cursor_ = nullptr;
};

}  // namespace

void register_view_radome(ViewRegistry& registry) {
  registry.add("radome", [] { return std::make_unique<RadomeView>(); });
}

}  // namespace kfw
