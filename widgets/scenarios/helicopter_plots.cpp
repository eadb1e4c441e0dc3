// Plots of the `helicopter` scenario (seed 000): angle, innovation, NIS, gain over time, the
// steady-state gain curve k1(β) with the operating point, and the gyro bias. NEES and whiteness
// are in the Consistency tab, the same for every scenario.
#include <qcustomplot.h>

#include <array>
#include <cmath>

#include "core/consistency.h"
#include "core/statistics.h"
#include "plot_kit.h"
#include "scenario_view.h"
#include "scenarios/helicopter/helicopter_model.h"
#include "scenarios/helicopter/indirect_kf.h"

namespace kfw {

namespace {

using helicopter::HelicopterResult;

class HelicopterView final : public ScenarioView {
 public:
  QList<PlotPanel> createPlots(QWidget* parent) override {
    using namespace plot;
    angle_ =
        makePlot(parent, "Angle: truth, sensor and estimate ± 2σ", "time (s)", "angle θ (deg)");
    angle_band_ = addBand(angle_, "estimate ± 2σ", color::kEstimate);
    angle_sensor_ = addGraph(angle_, "angle sensor", color::kSensor, Style::kDots);
    angle_truth_ = addGraph(angle_, "truth", color::kTruth, Style::kLine);
    angle_est_ = addGraph(angle_, "estimate of θ", color::kEstimate, Style::kLine);
    angle_cursor_ = addCursor(angle_);

    innov_ = makePlot(parent, "Innovation with ± 2√S", "time (s)", "innovation (deg)");
    innov_band_ = addBand(innov_, "± 2√S", color::kSecond);
    innov_y_ =
        addGraph(innov_, "innovation: measured − predicted θ", color::kEstimate, Style::kDots);
    innov_cursor_ = addCursor(innov_);

    nis_ = makePlot(parent, "NIS with 95 % χ²(1) bounds", "time (s)", "NIS (–)");
    setLog(nis_->yAxis);
    nis_y_ = addGraph(nis_, "NIS = y²/S", color::kEstimate, Style::kDots);
    nis_lo_ = addGraph(nis_, "χ²(1) 2.5 % / 97.5 %", color::kBound, Style::kDashed);
    nis_hi_ = addGraph(nis_, "", color::kBound, Style::kDashed);
    nis_hi_->removeFromLegend();
    nis_avg_ = addGraph(nis_, "moving average (50 updates)", color::kSecond);
    nis_avg_lo_ = addGraph(nis_, "95 % bounds of the average", color::kSecond, Style::kDashed);
    nis_avg_hi_ = addGraph(nis_, "", color::kSecond, Style::kDashed);
    nis_avg_hi_->removeFromLegend();
    nis_cursor_ = addCursor(nis_);

    gain_ = makePlot(parent, "Gain k1 over time", "time (s)", "gain k1 (–)");
    gain_k1_ = addGraph(gain_, "k1 (at angle updates)", color::kEstimate, Style::kStep);
    gain_ss_ = addGraph(gain_, "k1 steady state (DARE)", color::kSecond, Style::kDashed);
    gain_cursor_ = addCursor(gain_);

    curve_ = makePlot(parent, "Steady-state gain vs β = m·Ts²·N_ω/N_θ (seed 000, Fig. 3)", "β (–)",
                      "gain k1 (–)");
    setLog(curve_->xAxis);
    setLog(curve_->yAxis);
    curve_k1_ = addGraph(curve_, "k1(β)", color::kEstimate, Style::kLine);
    curve_p11_ = addGraphRight(curve_, "p11⁻/N_θ (β)", color::kThird, "p11⁻/N_θ (–)");
    setLog(curve_->yAxis2);
    curve_op_ = addGraph(curve_, "operating point", color::kSecond);
    curve_op_->setLineStyle(QCPGraph::lsNone);
    curve_op_->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, QPen(color::kSecond, 2),
                                               QBrush(color::kSecond), 9));
    curve_op_p11_ = curve_->addGraph(curve_->xAxis, curve_->yAxis2);
    curve_op_p11_->setLineStyle(QCPGraph::lsNone);
    curve_op_p11_->setScatterStyle(QCPScatterStyle(
        QCPScatterStyle::ssDiamond, QPen(color::kThird, 2), QBrush(color::kThird), 9));
    curve_op_p11_->removeFromLegend();
    curve_label_ = new QCPItemText(curve_);
    curve_label_->setPositionAlignment(Qt::AlignLeft | Qt::AlignTop);
    curve_label_->position->setType(QCPItemPosition::ptAxisRectRatio);
    curve_label_->position->setCoords(0.02, 0.03);
    curve_label_->setFont(QFont(curve_->font().family(), 8));
    curve_label_->setTextAlignment(Qt::AlignLeft);
    curve_label_->setPadding(QMargins(4, 2, 4, 2));
    curve_label_->setBrush(QBrush(QColor(255, 255, 255, 210)));
    curve_->axisRect()->insetLayout()->setInsetAlignment(0, Qt::AlignBottom | Qt::AlignRight);

    bias_ = makePlot(parent, "Gyro bias estimate ± 2σ", "time (s)", "bias b (deg/s)");
    bias_band_ = addBand(bias_, "estimate ± 2σ", color::kEstimate);
    bias_truth_ = addGraph(bias_, "true bias (simulated)", color::kTruth, Style::kLine);
    bias_est_ = addGraph(bias_, "estimate of b", color::kEstimate, Style::kLine);
    bias_cursor_ = addCursor(bias_);

    return {{"angle", "Angle", angle_},
            {"innovation", "Innovation", innov_},
            {"nis", "NIS", nis_},
            {"gain", "Gain over time", gain_},
            {"gain_curve", "Gain curve", curve_},
            {"bias", "Bias", bias_}};
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    auto r = std::dynamic_pointer_cast<const HelicopterResult>(result);
    if (!r) return;
    result_ = r;
    const std::size_t n = r->steps();
    two_sigma_theta_.resize(n);
    two_sigma_bias_.resize(n);
    two_sqrt_S_.resize(n);
    zero_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      two_sigma_theta_[i] = 2.0 * std::sqrt(std::max(0.0, r->P11[i]));
      two_sigma_bias_[i] = 2.0 * std::sqrt(std::max(0.0, r->P22[i]));
      two_sqrt_S_[i] = std::isfinite(r->S[i]) ? 2.0 * std::sqrt(r->S[i]) : kNoSample;
    }
    // Gain curve from the engine, wide enough to hold the operating point.
    const double b = r->beta;
    const double lo = std::min(1e-4, b / 10.0), hi = std::max(1e2, b * 10.0);
    const auto curve = helicopter::gain_curve(lo, hi, 200);
    plot::setSeries(curve_k1_, curve.beta, curve.k1, plot::kAll);
    plot::setSeries(curve_p11_, curve.beta, curve.p11_over_R, plot::kAll);
    curve_op_->data()->clear();
    curve_op_p11_->data()->clear();
    if (b > 0 && std::isfinite(b)) {
      curve_op_->addData(b, r->k1_closed);
      curve_op_p11_->addData(b, r->p11_over_R_steady);
    }
    curve_label_->setText(
        QString("β = %1   k1 = %2   p11⁻/N_θ = %3\nDARE k1 = %4  (m = %5, γ = %6)")
            .arg(b, 0, 'g', 3)
            .arg(r->k1_closed, 0, 'f', 4)
            .arg(r->p11_over_R_steady, 0, 'g', 4)
            .arg(r->k1_steady, 0, 'f', 4)
            .arg(values.count("m") ? values.at("m") : 1.0)
            .arg(values.count("gamma") ? values.at("gamma") : 0.0));
    curve_->xAxis->setRange(lo, hi);
    curve_->yAxis->setRange(curve.k1.front() / 1.5, 1.5);
    curve_->yAxis2->setRange(curve.p11_over_R.front() / 1.5, curve.p11_over_R.back() * 1.5);
    plot::replot(curve_);

    nis_lo_value_ = chi2_quantile(0.025, 1.0);
    nis_hi_value_ = chi2_quantile(0.975, 1.0);
    const auto avg_bounds = nis_bounds(1.0, r->nis_window);
    nis_avg_lo_value_ = avg_bounds.lo;
    nis_avg_hi_value_ = avg_bounds.hi;
    drawUpTo(cursor_);
  }

  // Ghosts: each snapshot's estimate, gain and bias as faded lines.
  void setSnapshots(const Snapshots& snapshots) override {
    for (const auto& g : ghosts_)
      plot::removePlottables({g.angle, g.gain, g.bias});
    ghosts_.clear();
    int i = 0;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const HelicopterResult>(result);
      if (!r) continue;
      const QColor c = plot::color::ghost(i++);
      Ghost g{r, plot::addGraph(angle_, "θ " + name, c),
              plot::addGraph(gain_, "k1 " + name, c, plot::Style::kStep),
              plot::addGraph(bias_, "b " + name, c)};
      ghosts_.push_back(g);
    }
    if (result_) drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

 private:
  void drawUpTo(std::size_t index) {
    const HelicopterResult& r = *result_;
    const std::size_t steps = r.steps();
    const bool all = index >= steps;
    const std::size_t n = all ? steps : index + 1;
    const double t0 = steps ? r.t.front() : 0.0, t1 = steps ? r.t.back() : 1.0;
    const double tc = steps ? r.t[std::min(n, steps) - 1] : 0.0;
    using plot::setSeries;
    plot::setBand(angle_band_, r.t, r.theta, two_sigma_theta_, n);
    setSeries(angle_sensor_, r.t, r.angle, n);
    setSeries(angle_truth_, r.t, r.truth, n);
    setSeries(angle_est_, r.t, r.theta, n);
    plot::setBand(innov_band_, r.t, zero_, two_sqrt_S_, n);
    setSeries(innov_y_, r.t, r.innovation, n);
    setSeries(nis_y_, r.t, r.nis, n);
    // Constant lines as two points: a dashed pen over thousands of vertices is slow to stroke.
    const std::vector<double> span{t0, tc};
    setSeries(nis_lo_, span, {nis_lo_value_, nis_lo_value_}, 2);
    setSeries(nis_hi_, span, {nis_hi_value_, nis_hi_value_}, 2);
    setSeries(nis_avg_, r.t, r.nis_avg, n);
    setSeries(nis_avg_lo_, span, {nis_avg_lo_value_, nis_avg_lo_value_}, 2);
    setSeries(nis_avg_hi_, span, {nis_avg_hi_value_, nis_avg_hi_value_}, 2);
    setSeries(gain_k1_, r.t, r.k1, n);
    setSeries(gain_ss_, span, {r.k1_steady, r.k1_steady}, 2);
    plot::setBand(bias_band_, r.t, r.bias, two_sigma_bias_, n);
    setSeries(bias_est_, r.t, r.bias, n);
    setSeries(bias_truth_, r.t, r.bias_truth, n);
    bias_truth_->setVisible(!r.bias_truth.empty());
    if (r.bias_truth.empty()) {
      bias_truth_->removeFromLegend();
    } else {
      bias_truth_->addToLegend();
    }
    for (const auto& g : ghosts_) {
      const std::size_t gn = std::min(n, g.result->steps());
      setSeries(g.angle, g.result->t, g.result->theta, gn);
      setSeries(g.gain, g.result->t, g.result->k1, gn);
      setSeries(g.bias, g.result->t, g.result->bias, gn);
    }
    // The start-up transient (P0) runs off the top rather than flattening the rest.
    for (QCustomPlot* p : {angle_, innov_, nis_, gain_, bias_})
      plot::rescale(p, t0, t1, plot::settleTime(t0, t1));
    // Keep the gain axis readable: the start-up transient (k1 ≈ 1) would flatten the steady part.
    const double k_ss = std::isfinite(r.k1_steady) ? r.k1_steady : 0.5;
    gain_->yAxis->setRange(0.0, std::clamp(2.5 * k_ss, 1e-6, 1.05));
    for (auto* c : {angle_cursor_, innov_cursor_, nis_cursor_, gain_cursor_, bias_cursor_}) {
      plot::setCursorAt(c, tc, !all);
    }
    for (QCustomPlot* p : {angle_, innov_, nis_, gain_, bias_})
      plot::replot(p);
  }

  struct Ghost {
    std::shared_ptr<const HelicopterResult> result;
    QCPGraph *angle, *gain, *bias;
  };
  std::vector<Ghost> ghosts_;
  std::shared_ptr<const HelicopterResult> result_;
  std::size_t cursor_ = plot::kAll;
  std::vector<double> two_sigma_theta_, two_sigma_bias_, two_sqrt_S_, zero_;
  double nis_lo_value_ = 0.0, nis_hi_value_ = 0.0, nis_avg_lo_value_ = 0.0, nis_avg_hi_value_ = 0.0;

  QCustomPlot *angle_ = nullptr, *innov_ = nullptr, *nis_ = nullptr, *gain_ = nullptr,
              *curve_ = nullptr, *bias_ = nullptr;
  QCPGraph *nis_avg_ = nullptr, *nis_avg_lo_ = nullptr, *nis_avg_hi_ = nullptr;
  plot::Band angle_band_, innov_band_, bias_band_;
  QCPGraph *angle_sensor_ = nullptr, *angle_truth_ = nullptr, *angle_est_ = nullptr;
  QCPGraph *innov_y_ = nullptr, *nis_y_ = nullptr, *nis_lo_ = nullptr, *nis_hi_ = nullptr;
  QCPGraph *gain_k1_ = nullptr, *gain_ss_ = nullptr;
  QCPGraph *curve_k1_ = nullptr, *curve_p11_ = nullptr, *curve_op_ = nullptr,
           *curve_op_p11_ = nullptr;
  QCPItemText* curve_label_ = nullptr;
  QCPGraph *bias_truth_ = nullptr, *bias_est_ = nullptr;
  QCPItemStraightLine *angle_cursor_ = nullptr, *innov_cursor_ = nullptr, *nis_cursor_ = nullptr,
                      *gain_cursor_ = nullptr, *bias_cursor_ = nullptr;
};

}  // namespace

void register_view_helicopter(ViewRegistry& registry) {
  registry.add("helicopter", [] { return std::make_unique<HelicopterView>(); });
}

}  // namespace kfw
