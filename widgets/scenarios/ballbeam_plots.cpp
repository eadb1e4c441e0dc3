// Plots of the `ballbeam` scenario (seed 003): ball position (truth, raw sensor with spikes,
// estimate, flagged samples), sensor voltage with and without the circuit (Fig. 7), beam angle and
// command, innovation ± 2√S, α and β versus λ with the operating point, and the step response
// noise-free / detection on / detection off overlaid (Figs. 8, 9); pinned tunings as faded ghosts.
// Legend text stays plain: at the legend's 8 pt a combining circumflex (x̂) is misplaced and there
// is no subscript c, so "estimate of x" and "set-point" rather than x̂ and x_c.
#include <qcustomplot.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "plot_blocks.h"
#include "plot_kit.h"
#include "scenario_view.h"
#include "scenarios/ballbeam/alpha_beta.h"
#include "scenarios/ballbeam/ballbeam_result.h"

namespace kfw {

namespace {

using ballbeam::BallbeamResult;

QCPGraph* addMarkers(QCustomPlot* p, const QString& name, const QColor& c,
                     QCPScatterStyle::ScatterShape shape, double size) {
  QCPGraph* g = plot::addGraph(p, name, c, plot::Style::kDots);
  g->setScatterStyle(QCPScatterStyle(shape, QPen(c, 1.5), Qt::NoBrush, size));
  return g;
}

class BallbeamView final : public ScenarioView {
 public:
  QList<PlotPanel> createPlots(QWidget* parent) override {
    using namespace plot;
    pos_ = makePlot(parent, "Ball position: truth, raw sensor, estimate", "time (s)",
                    "ball position x (m)");
    pos_band_ = addBand(pos_, "estimate ± 2σ", color::kEstimate);
    pos_sensor_ = addGraph(pos_, "raw sensor x̃", color::kSensor, Style::kDots);
    pos_lost_ = addMarkers(pos_, "contact lost", color::kSecond, QCPScatterStyle::ssCross, 6);
    pos_setpoint_ = addGraph(pos_, "set-point", color::kFourth, Style::kDashed);
    pos_truth_ = addGraph(pos_, "truth", color::kTruth, Style::kLine);
    pos_est_ = addGraph(pos_, "estimate of x", color::kEstimate, Style::kLine);
    pos_cursor_ = addCursor(pos_);
    pos_fell_ = addFellMarker(pos_);

    volt_ = makePlot(parent, "Contact sensor voltage (Jang et al. 2014, Fig. 7)", "time (s)",
                     "sensor output voltage (V)");
    volt_raw_ = addGraph(volt_, "without circuit (a)", color::kSecond, Style::kLine);
    volt_circ_ = addGraph(volt_, "with circuit (b)", color::kEstimate, Style::kLine);
    volt_zero_ = addMarkers(volt_, "0 V detections", color::kTruth, QCPScatterStyle::ssCircle, 5);
    volt_cursor_ = addCursor(volt_);

    beam_ = makePlot(parent, "Beam angle and command", "time (s)", "beam angle (rad)");
    beam_cmd_ = addGraph(beam_, "angle command", color::kFourth, Style::kLine);
    beam_theta_ = addGraph(beam_, "angle θ", color::kTruth, Style::kLine);
    beam_V_ = addGraphRight(beam_, "motor voltage V", color::kFifth, "motor voltage V (V)");
    beam_cursor_ = addCursor(beam_);

    innov_ = std::make_unique<InnovationPlot>(parent, "Innovation with ± 2√S", "innovation (m)",
                                              "innovation x̃ − x̄");

    curve_ =
        makePlot(parent, "α-β gains vs tracking index λ = Ts²√(Q/R) (Jang et al. 2014, eq. 16)",
                 "λ (–)", "gain (–)");
    setLog(curve_->xAxis);
    setLog(curve_->yAxis);
    curve_alpha_ = addGraph(curve_, "α(λ)", color::kEstimate, Style::kLine, 1.8);
    curve_beta_ = addGraph(curve_, "β(λ)", color::kThird, Style::kLine, 1.8);
    curve_op_ = addGraph(curve_, "operating point", color::kSecond);
    curve_op_->setLineStyle(QCPGraph::lsNone);
    curve_op_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, QPen(color::kSecond, 2),
                                               QBrush(color::kSecond), 9));
    curve_label_ = addNote(curve_);

    step_ = makePlot(
        parent, "Step response: noise-free vs detection on / off (Jang et al. 2014, Figs. 8, 9)",
        "time (s)", "ball position x (m)");
    step_setpoint_ = addGraph(step_, "set-point", color::kFourth, Style::kDashed);
    step_off_ = addGraph(step_, "detection off", color::kSecond, Style::kLine, 1.2);
    step_on_ = addGraph(step_, "detection on", color::kEstimate, Style::kLine, 1.6);
    step_clean_ = addGraph(step_, "noise-free", color::kTruth, Style::kDashed, 1.4);
    step_cursor_ = addCursor(step_);
    step_fell_ = addFellMarker(step_);

    return {{"position", "Ball position", pos_},
            {"voltage", "Sensor voltage", volt_},
            {"beam", "Beam angle", beam_},
            {"innovation", "Innovation", innov_->plot()},
            {"gain_curve", "α-β gain curve", curve_},
            {"step", "Step response", step_}};
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    auto r = std::dynamic_pointer_cast<const BallbeamResult>(result);
    if (!r) return;
    result_ = r;
    const auto& tr = r->trace;
    const std::size_t n = r->steps();
    two_sigma_.assign(n, kNoSample);
    lost_x_.assign(n, kNoSample);
    zero_v_.assign(n, kNoSample);
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isfinite(tr.P11[i])) two_sigma_[i] = 2.0 * std::sqrt(std::max(0.0, tr.P11[i]));
      const bool lost = tr.v_sensor[i] == 0.0 || !std::isfinite(tr.x_meas[i]);
      if (lost) {
        lost_x_[i] = tr.x_meas[i];
        zero_v_[i] = 0.0;
      }
    }
    innov_->setData(&r->t, &tr.innovation, &tr.S);
    const bool detection = values.count("detection") && values.at("detection") != 0;
    pos_lost_->setName(detection ? "contact lost: flagged, skipped"
                                 : "contact lost: used (no circuit)");

    // α, β vs λ from the engine, wide enough to hold the operating point.
    const double l = r->lambda;
    const double lo = std::min(1e-4, l / 10.0), hi = std::max(1e2, l * 10.0);
    const auto curve = ballbeam::gain_curve(lo, hi, 200);
    plot::setSeries(curve_alpha_, curve.lambda, curve.alpha, plot::kAll);
    plot::setSeries(curve_beta_, curve.lambda, curve.beta, plot::kAll);
    curve_op_->data()->clear();
    if (l > 0 && std::isfinite(l)) {
      curve_op_->addData(l, r->alpha);
      curve_op_->addData(l, r->beta);
    }
    curve_label_->setText(QString("λ = %1   α = %2   β = %3\nDARE α = %4   β = %5   (Ts = %6 s)")
                              .arg(l, 0, 'g', 3)
                              .arg(r->alpha, 0, 'f', 4)
                              .arg(r->beta, 0, 'f', 4)
                              .arg(r->alpha_dare, 0, 'f', 4)
                              .arg(r->beta_dare, 0, 'f', 4)
                              .arg(r->Ts_s, 0, 'g', 3));
    if (!plot::userZoomedX(curve_)) curve_->xAxis->setRange(lo, hi);
    // Down to the smallest β drawn (no empty decade under the curves).
    const double beta_lo = curve.beta.empty() ? 1e-5 : curve.beta.front();
    if (!plot::userZoomedY(curve_)) curve_->yAxis->setRange(std::min(beta_lo, r->beta) / 2, 3.0);
    plot::replot(curve_);
    drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

  // Ghosts: each pinned tuning's estimate (position plot) and the true ball position of its own
  // run (step plot: detection on or off as pinned, or the log's truth in replay), faded.
  void setSnapshots(const Snapshots& snapshots) override {
    for (const auto& g : ghosts_)
      plot::removePlottables({g.estimate, g.step});
    ghosts_.clear();
    int i = 0;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const BallbeamResult>(result);
      if (!r) continue;
      const int c = i++;
      const QString run = !r->closed_loop   ? "truth"
                          : r->detection_on ? "detection on"
                                            : "detection off";
      ghosts_.push_back({r, plot::addGhost(pos_, "estimate of x [pinned: " + name + "]", c),
                         plot::addGhost(step_, "[pinned: " + name + "] (" + run + ")", c)});
    }
    if (result_) drawUpTo(cursor_);
  }

 private:
  void drawUpTo(std::size_t index) {
    const BallbeamResult& r = *result_;
    const auto& tr = r.trace;
    const std::size_t steps = r.steps();
    const bool all = index >= steps;
    const std::size_t n = all ? steps : index + 1;
    const double t0 = steps ? r.t.front() : 0.0, t1 = steps ? r.t.back() : 1.0;
    const double tc = steps ? r.t[std::min(n, steps) - 1] : 0.0;
    using plot::setSeries;
    plot::setBand(pos_band_, r.t, tr.x_hat, two_sigma_, n);
    setSeries(pos_sensor_, r.t, tr.x_meas, n);
    setSeries(pos_lost_, r.t, lost_x_, n);
    setSeries(pos_setpoint_, r.t, tr.setpoint, n);
    setSeries(pos_truth_, r.t, tr.x_true, n);
    setSeries(pos_est_, r.t, tr.x_hat, n);
    setSeries(volt_raw_, r.t, tr.v_raw, n);
    setSeries(volt_circ_, r.t, tr.v_sensor, n);
    setSeries(volt_zero_, r.t, zero_v_, n);
    setSeries(beam_cmd_, r.t, tr.theta_c, n);
    setSeries(beam_theta_, r.t, tr.theta, n);
    setSeries(beam_V_, r.t, tr.V, n);
    setSeries(step_setpoint_, r.t, tr.setpoint, n);
    // The variants run on the whole loop's grid (a ball that fell ends early).
    const auto& grid = r.t_loop.empty() ? r.t : r.t_loop;
    const std::size_t grid_n = all ? grid.size() : n;
    setSeries(step_clean_, grid, r.x_noise_free, grid_n);
    setSeries(step_on_, grid, r.x_detect_on, grid_n);
    setSeries(step_off_, grid, r.x_detect_off, grid_n);
    const double fell = tr.left_beam_at_s;
    for (auto* m : {pos_fell_, step_fell_})
      plot::setCursorAt(m, fell, std::isfinite(fell));
    for (const auto& g : ghosts_) {
      // Cut at the cursor's time (a pinned tuning may have another Ts).
      const auto& gt = g.result->t;
      const std::size_t gn =
          all ? gt.size()
              : static_cast<std::size_t>(std::upper_bound(gt.begin(), gt.end(), tc) - gt.begin());
      setSeries(g.estimate, gt, g.result->trace.x_hat, gn);
      setSeries(g.step, gt, g.result->trace.x_true, gn);
    }
    // The estimator's start-up (P0: ±0.2 m bands for the first 0.3 s) would set the position and
    // innovation axes and flatten the ±4 mm steady innovations; they run off the top instead.
    const double settle = plot::settleTime(t0, t1);
    plot::rescale(pos_, t0, t1, settle);
    innov_->draw(plot::frameAt(r.t, index));
    for (QCustomPlot* p : {volt_, beam_, step_})
      plot::rescale(p, t0, t1);
    // The beam's motor-voltage axis follows its own data (the saturation limits stay visible).
    double v_lo = -1.0, v_hi = 1.0;
    for (std::size_t i = 0; i < std::min(n, tr.V.size()); ++i) {
      if (!std::isfinite(tr.V[i])) continue;
      v_lo = std::min(v_lo, tr.V[i]);
      v_hi = std::max(v_hi, tr.V[i]);
    }
    const double v_pad = 0.08 * (v_hi - v_lo);
    if (!plot::userZoomedY(beam_)) beam_->yAxis2->setRange(v_lo - v_pad, v_hi + v_pad);
    for (auto* c : {pos_cursor_, volt_cursor_, beam_cursor_, step_cursor_})
      plot::setCursorAt(c, tc, !all);
    for (QCustomPlot* p : {pos_, volt_, beam_, step_})
      plot::replot(p);
  }

  // A dashed black line where the ball left the beam.
  static QCPItemStraightLine* addFellMarker(QCustomPlot* p) {
    QCPItemStraightLine* line = plot::addCursor(p);
    line->setPen(QPen(Qt::black, 1.2, Qt::DashLine));
    return line;
  }

  struct Ghost {
    std::shared_ptr<const BallbeamResult> result;
    QCPGraph *estimate, *step;
  };
  std::vector<Ghost> ghosts_;
  std::shared_ptr<const BallbeamResult> result_;
  std::size_t cursor_ = plot::kAll;
  std::vector<double> two_sigma_, lost_x_, zero_v_;

  QCustomPlot *pos_ = nullptr, *volt_ = nullptr, *beam_ = nullptr, *curve_ = nullptr,
              *step_ = nullptr;
  plot::Band pos_band_;
  std::unique_ptr<plot::InnovationPlot> innov_;
  QCPGraph *pos_sensor_ = nullptr, *pos_lost_ = nullptr, *pos_setpoint_ = nullptr,
           *pos_truth_ = nullptr, *pos_est_ = nullptr;
  QCPGraph *volt_raw_ = nullptr, *volt_circ_ = nullptr, *volt_zero_ = nullptr;
  QCPGraph *beam_cmd_ = nullptr, *beam_theta_ = nullptr, *beam_V_ = nullptr;
  QCPGraph *curve_alpha_ = nullptr, *curve_beta_ = nullptr, *curve_op_ = nullptr;
  QCPItemText* curve_label_ = nullptr;
  QCPGraph *step_setpoint_ = nullptr, *step_clean_ = nullptr, *step_on_ = nullptr,
           *step_off_ = nullptr;
  QCPItemStraightLine *pos_cursor_ = nullptr, *volt_cursor_ = nullptr, *beam_cursor_ = nullptr,
                      *step_cursor_ = nullptr;
  QCPItemStraightLine *pos_fell_ = nullptr, *step_fell_ = nullptr;
};

}  // namespace

void register_view_ballbeam(ViewRegistry& registry) {
  registry.add("ballbeam", [] { return std::make_unique<BallbeamView>(); });
}

}  // namespace kfw
