// Plots of the `helicopter` scenario (seed 000): angle, innovation, NIS, gain over time, the
// steady-state gain curve k1(β) with the operating point, and the gyro bias. NEES and whiteness
// are in the Consistency tab, the same for every scenario.
#include <qcustomplot.h>

#include <array>
#include <cmath>

#include "core/statistics.h"
#include "filter/consistency.h"
#include "plot_blocks.h"
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
    angle_ = std::make_unique<EstimatePlot>(parent, "Angle: truth, sensor and estimate ± 2σ",
                                            "angle θ (deg)", "estimate of θ", "angle sensor");
    innov_ = std::make_unique<InnovationPlot>(parent, "Innovation with ± 2√S", "innovation (deg)",
                                              "innovation: measured − predicted θ");
    nis_ = std::make_unique<NisPlot>(parent, "NIS with 95 % χ²(1) bounds");

    gain_ = makePlot(parent, "Gain k1 over time", "time (s)", "gain k1 (–)");
    gain_k1_ = addGraph(gain_, "k1 (at angle updates)", color::kEstimate, Style::kStep);
    gain_ss_ = addGraph(gain_, "k1 steady state (DARE)", color::kSecond, Style::kDashed);
    gain_cursor_ = addCursor(gain_);

    curve_ = makePlot(
        parent, "Steady-state gain vs β = m·Ts²·N_ω/N_θ (Kim et al., helicopter attitude, Fig. 3)",
        "β (–)", "gain k1 (–)");
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
    curve_op_p11_->setName("");  // one legend entry for both operating points
    curve_op_p11_->removeFromLegend();
    curve_label_ = addNote(curve_);

    bias_ = std::make_unique<EstimatePlot>(parent, "Gyro bias estimate ± 2σ", "bias b (deg/s)",
                                           "estimate of b", QString(), "true bias (simulated)");

    return {{"angle", "Angle", angle_->plot()},   {"innovation", "Innovation", innov_->plot()},
            {"nis", "NIS", nis_->plot()},         {"gain", "Gain over time", gain_},
            {"gain_curve", "Gain curve", curve_}, {"bias", "Bias", bias_->plot()}};
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    auto r = std::dynamic_pointer_cast<const HelicopterResult>(result);
    if (!r) return;
    result_ = r;
    angle_->setData(&r->t, &r->theta, &r->P11, r->truth.empty() ? nullptr : &r->truth, &r->angle);
    innov_->setData(&r->t, &r->innovation, &r->S);
    nis_->setData(&r->t, &r->nis, 1.0, &r->nis_avg, r->nis_window);
    bias_->setData(&r->t, &r->bias, &r->P22, r->bias_truth.empty() ? nullptr : &r->bias_truth);
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
    if (!plot::userZoomedX(curve_)) curve_->xAxis->setRange(lo, hi);
    if (!plot::userZoomedY(curve_)) {
      curve_->yAxis->setRange(curve.k1.front() / 1.5, 1.5);
      curve_->yAxis2->setRange(curve.p11_over_R.front() / 1.5, curve.p11_over_R.back() * 1.5);
    }
    plot::replot(curve_);

    drawUpTo(cursor_);
  }

  // Ghosts: each snapshot's estimate, gain and bias as faded lines.
  void setSnapshots(const Snapshots& snapshots) override {
    for (const auto& g : ghosts_)
      plot::removePlottables({g.gain});
    ghosts_.clear();
    QList<plot::GhostSeries> angle, bias;
    int i = 0;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const HelicopterResult>(result);
      if (!r) continue;
      angle.push_back({"estimate of θ [pinned: " + name + "]", &r->t, &r->theta});
      bias.push_back({"bias [pinned: " + name + "]", &r->t, &r->bias});
      ghosts_.push_back(
          {r, plot::addGhost(gain_, "k1 [pinned: " + name + "]", i, plot::Style::kStep)});
      ++i;
    }
    angle_->setGhosts(angle);
    bias_->setGhosts(bias);
    if (result_) drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

 private:
  void drawUpTo(std::size_t index) {
    const HelicopterResult& r = *result_;
    const plot::Frame f = plot::frameAt(r.t, index);
    angle_->draw(f);
    innov_->draw(f);
    nis_->draw(f);
    bias_->draw(f);
    plot::setSeries(gain_k1_, r.t, r.k1, f.n);
    plot::setLevel(gain_ss_, f, r.k1_steady);
    for (const auto& g : ghosts_) {
      plot::setSeries(g.gain, g.result->t, g.result->k1, plot::stepsUpTo(g.result->t, f));
    }
    plot::rescale(gain_, f.t0, f.t1, f.settle());
    // Keep the gain axis readable: the start-up transient (k1 ≈ 1) would flatten the steady part.
    // Pinned tunings' steady gains stay inside the axis too.
    double k_ss = std::isfinite(r.k1_steady) ? r.k1_steady : 0.5;
    for (const auto& g : ghosts_) {
      if (std::isfinite(g.result->k1_steady)) k_ss = std::max(k_ss, g.result->k1_steady);
    }
    if (!plot::userZoomedY(gain_)) gain_->yAxis->setRange(0.0, std::clamp(2.5 * k_ss, 1e-6, 1.05));
    plot::setCursorAt(gain_cursor_, f.tc, !f.all);
    plot::replot(gain_);
  }

  struct Ghost {
    std::shared_ptr<const HelicopterResult> result;
    QCPGraph* gain;
  };
  std::vector<Ghost> ghosts_;
  std::shared_ptr<const HelicopterResult> result_;
  std::size_t cursor_ = plot::kAll;

  std::unique_ptr<plot::EstimatePlot> angle_, bias_;
  std::unique_ptr<plot::InnovationPlot> innov_;
  std::unique_ptr<plot::NisPlot> nis_;
  QCustomPlot *gain_ = nullptr, *curve_ = nullptr;
  QCPGraph *gain_k1_ = nullptr, *gain_ss_ = nullptr;
  QCPGraph *curve_k1_ = nullptr, *curve_p11_ = nullptr, *curve_op_ = nullptr,
           *curve_op_p11_ = nullptr;
  QCPItemText* curve_label_ = nullptr;
  QCPItemStraightLine* gain_cursor_ = nullptr;
};

}  // namespace

void register_view_helicopter(ViewRegistry& registry) {
  registry.add("helicopter", [] { return std::make_unique<HelicopterView>(); });
}

}  // namespace kfw
