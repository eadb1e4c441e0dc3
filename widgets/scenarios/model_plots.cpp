// Plots of any model declared in a preset file (scenario "model"), laid out from the model: per
// state the estimate ± 2σ with truth; per measurement component the measured and predicted value
// and the innovation ± 2√S; per channel the NIS with χ² bounds; the gains over time with the DARE
// steady state; the steady-state gains versus a parameter chosen under the sliders; and one panel
// per plot block the file asks for ("plots", widgets/plots/); a model with modes adds the IMM
// panels (model_imm_widgets.h); model.first_panels puts panels first. Nothing here knows a
// particular model.
#include <qcustomplot.h>

#include <QComboBox>
#include <QFormLayout>
#include <QFutureWatcher>
#include <QGroupBox>
#include <QSignalBlocker>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <cmath>
#include <optional>

#include "data/wrap_gaps.h"
#include "experiment/gain_curve.h"
#include "gain_curve_plot.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "plot_blocks.h"
#include "plot_kit.h"
#include "plot_look.h"
#include "plot_text.h"
#include "plots/block_drawer.h"
#include "scenario_view.h"
#include "scenarios/model_imm_widgets.h"

namespace kfw {

namespace {

using model::ModelResult;

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

using plot::withUnit;

class ModelView final : public ScenarioView {
 public:
  ModelView() {
    connect(&curve_watcher_, &QFutureWatcherBase::finished, this, [this] { curveReady(); });
  }
  ~ModelView() override { curve_watcher_.waitForFinished(); }

  void setScenario(std::shared_ptr<const Scenario> scenario) override {
    scenario_ = std::move(scenario);
    if (scenario_) layout_ = model_layout_of(*scenario_);
    // A gain curve only where a steady state exists: a linear time-invariant model.
    const bool lti = layout_ && layout_->time_invariant;
    curve_keys_ = lti ? gain_curve_parameters(*scenario_) : std::vector<std::string>{};
    curve_key_.clear();  // chosen from the first result's values (setResult)
  }
  void setDataset(std::shared_ptr<const Dataset> data) override { data_ = std::move(data); }
  // Until the latest curve is drawn (a finished future's signal may still be queued).
  bool busy() const override { return curve_outstanding_; }

  QWidget* createControls(QWidget* parent) override {
    if (curve_keys_.empty()) return nullptr;
    auto* box = new QGroupBox("Gain curve", parent);
    auto* form = new QFormLayout(box);
    auto* combo = new QComboBox(box);
    combo->setObjectName("gainCurveParameter");
    combo->setToolTip("The parameter along the steady-state gain curve (the other values stay)");
    for (const auto& k : curve_keys_) {
      const ParamSpec* p = scenario_->params().find(k);
      combo->addItem(q(p && !p->label.empty() ? p->label : k), q(k));
    }
    combo_ = combo;
    form->addRow("versus", combo);
    connect(combo, &QComboBox::currentIndexChanged, this, [this, combo](int i) {
      curve_key_ = combo->itemData(i).toString().toStdString();
      if (result_) requestCurve();
    });
    return box;
  }

  QList<PlotPanel> createPlots(QWidget* parent) override {
    QList<PlotPanel> out;
    if (!layout_) return out;
    for (const auto& s : layout_->states) {
      const QString label = q(s.label);
      states_.push_back(std::make_unique<plot::EstimatePlot>(
          parent, QString("%1: truth and estimate ± 2σ").arg(label), withUnit(label, s.unit),
          "estimate of " + q(s.name)));
      states_.back()->setTurn(s.turn);  // an angle's lines break at its wrap
      out.push_back({q("state." + s.name), label, states_.back()->plot()});
    }
    for (const auto& c : layout_->channels) {
      const QString cl = q(c.label);
      for (const auto& r : c.roles) {
        Component comp;
        comp.measured =
            plot::makePlot(parent, QString("%1: measured and predicted %2").arg(cl, q(r.name)),
                           "time (s)", withUnit(q(r.name), r.unit));
        comp.z = plot::addGraph(comp.measured, "measured " + q(r.name), plot::color::kSensor,
                                plot::Style::kDots);
        // An angle's prediction is a line with a gap at each wrap (setResult).
        comp.zhat = plot::addGraph(comp.measured, "predicted ẑ (before the update)",
                                   plot::color::kEstimate, plot::Style::kLine);
        comp.turn = r.turn;
        comp.cursor = plot::addCursor(comp.measured);
        comp.innovation = std::make_unique<plot::InnovationPlot>(
            parent, QString("%1: innovation of %2 with ± 2√S").arg(cl, q(r.name)),
            withUnit("innovation", r.unit), "innovation: measured − predicted");
        out.push_back(
            {q("measured." + c.name + "." + r.name), "measured " + q(r.name), comp.measured});
        out.push_back({q("innovation." + c.name + "." + r.name), "innovation " + q(r.name),
                       comp.innovation->plot()});
        components_.push_back(std::move(comp));
      }
      nis_.push_back(std::make_unique<plot::NisPlot>(
          parent, QString("%1: NIS with 95 % χ²(%2) bounds").arg(cl).arg(c.roles.size())));
      out.push_back({q("nis." + c.name), "NIS " + cl, nis_.back()->plot()});
    }
    const bool lti = layout_->time_invariant;
    gain_ = plot::makePlot(parent,
                           lti ? "Gains over time (dashed: DARE steady state)" : "Gains over time",
                           "time (s)", "gain (–)");
    gain_cursor_ = plot::addCursor(gain_);
    out.push_back({"gain", "Gains over time", gain_});
    if (lti) {
      curve_ = std::make_unique<plot::GainCurvePlot>(parent);
      out.push_back({"gain_curve", "Gain curve", curve_->plot()});
    }
    imm_.create(parent, *layout_, out);
    for (const auto& b : layout_->plots) {
      if (auto d = plot::makeBlockDrawer(parent, b, *scenario_)) {
        out.push_back({q(b.id), d->title(), d->plot()});
        if (b.kind == "series") time_blocks_.push_back(d->plot());
        blocks_.push_back(std::move(d));
      }
    }
    // model.first_panels first, in the file's order; the others after, in theirs.
    const auto& first = layout_->first_panels;
    const auto rank = [&](const PlotPanel& p) {
      return std::find(first.begin(), first.end(), p.name.toStdString()) - first.begin();
    };
    std::stable_sort(out.begin(), out.end(),
                     [&](const PlotPanel& a, const PlotPanel& b) { return rank(a) < rank(b); });
    markPresented(out);
    return out;
  }

  // Presentation's default: the panels the file puts first; else the first innovation and the
  // first NIS, which show a tuning (a state's ramp of 1 750 m hides its band).
  void markPresented(QList<PlotPanel>& out) const {
    if (!layout_->first_panels.empty()) return;  // the first two: the file's choice
    for (const char* prefix : {"innovation.", "nis."}) {
      for (PlotPanel& p : out) {
        if (p.name.startsWith(prefix)) {
          p.presented = true;
          break;
        }
      }
    }
  }

  void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) override {
    auto r = std::dynamic_pointer_cast<const ModelResult>(result);
    if (!r || !layout_ || r->n() != states_.size()) return;
    result_ = r;
    values_ = values;
    for (std::size_t i = 0; i < states_.size(); ++i) {
      const bool truth = !r->truth[i].empty();
      states_[i]->setData(&r->t, &r->x[i], &r->P[r->diag[i]], truth ? &r->truth[i] : nullptr);
      // No truth (a log without it, a state the world does not simulate): no "truth" in the title.
      kfw::setTitle(states_[i]->plot(),
                    QString(truth ? "%1: truth and estimate ± 2σ" : "%1: estimate ± 2σ")
                        .arg(q(layout_->states[i].label)));
    }
    // Components in channel order: z rows and channel components line up.
    std::size_t row = 0;
    for (std::size_t c = 0; c < r->chans.size() && c < nis_.size(); ++c) {
      const auto& ch = r->chans[c];
      for (std::size_t j = 0; j < ch.y.size() && row < components_.size(); ++j, ++row) {
        Component& comp = components_[row];
        comp.z_row = row;
        const auto& z = r->z[row];
        comp.zhat_y.assign(z.size(), kNoSample);
        for (std::size_t k = 0; k < z.size(); ++k)
          comp.zhat_y[k] = z[k] - ch.y[j][k];  // NaN where the channel did not update
        if (comp.turn > 0.0) comp.zhat_gapped = gap_wraps(r->t, comp.zhat_y, comp.turn);
        comp.innovation->setData(&r->t, &ch.y[j], &ch.S[j]);
        comp.innovation->setRejected(&ch.gated_rows, "rejected by the gate");
      }
      nis_[c]->setData(&r->t, &ch.nis, static_cast<double>(ch.y.size()));
    }
    rebuildGainGraphs();
    imm_.setResult(*r);
    const plot::BlockInput in{*scenario_, *r, values_, data_.get()};
    for (auto& b : blocks_)
      b->setResult(in);
    markEvent(*r);
    if (curve_key_.empty() && !curve_keys_.empty()) {
      curve_key_ = default_gain_curve_parameter(*scenario_, values_, data_.get());
      if (curve_key_.empty()) curve_key_ = curve_keys_.front();
      if (combo_) {
        const QSignalBlocker block(combo_);
        combo_->setCurrentIndex(combo_->findData(q(curve_key_)));
      }
    }
    requestCurve();
    drawUpTo(cursor_);
  }

  void setSnapshots(const Snapshots& snapshots) override {
    ghosts_.clear();
    std::vector<QList<plot::GhostSeries>> per_state(states_.size());
    std::vector<plot::BlockDrawer::Ghost> block_ghosts;
    for (const auto& [name, result] : snapshots) {
      auto r = std::dynamic_pointer_cast<const ModelResult>(result);
      if (!r || r->n() != states_.size()) continue;
      ghosts_.push_back(r);
      block_ghosts.emplace_back(name, r.get());
      for (std::size_t i = 0; i < states_.size(); ++i)
        per_state[i].push_back(
            {q(layout_->states[i].name) + " [pinned: " + name + "]", &r->t, &r->x[i]});
    }
    for (std::size_t i = 0; i < states_.size(); ++i)
      states_[i]->setGhosts(per_state[i]);
    for (auto& b : blocks_)
      b->setGhosts(block_ghosts);
    std::vector<std::pair<QString, std::shared_ptr<const ModelResult>>> imm_pins;
    for (const auto& [name, result] : snapshots)
      imm_pins.emplace_back(name, std::dynamic_pointer_cast<const ModelResult>(result));
    imm_.setSnapshots(imm_pins);
    if (result_) drawUpTo(cursor_);
  }

  void setCursor(std::size_t index) override {
    cursor_ = index;
    if (result_) drawUpTo(index);
  }

 private:
  struct Component {
    QCustomPlot* measured = nullptr;
    QCPGraph *z = nullptr, *zhat = nullptr;
    QCPItemStraightLine* cursor = nullptr;
    std::unique_ptr<plot::InnovationPlot> innovation;
    std::size_t z_row = 0;
    std::vector<double> zhat_y;
    double turn = 0.0;         // an angle's full turn; 0: not an angle
    GappedSeries zhat_gapped;  // an angle's prediction with a gap at each wrap
  };
  struct GainGraph {
    const std::vector<double>* k = nullptr;
    QCPGraph* live = nullptr;
    QCPGraph* steady = nullptr;  // null when there is no DARE value for the entry
    double steady_value = 0.0;
  };

  // A closed loop that an event ended (the ball left the beam, model.world.events): a dashed line
  // at its time on each time panel of the states, measurements and series blocks, labelled.
  void markEvent(const ModelResult& r) {
    for (QCPAbstractItem* item : event_items_)
      item->parentPlot()->removeItem(item);
    event_items_.clear();
    if (!r.event) return;
    std::vector<QCustomPlot*> plots = time_blocks_;
    for (auto& s : states_)
      plots.push_back(s->plot());
    for (auto& c : components_)
      plots.push_back(c.measured);
    const QColor red(190, 30, 30);
    for (QCustomPlot* p : plots) {
      auto* line = new QCPItemStraightLine(p);
      line->point1->setCoords(r.event->t, 0.0);
      line->point2->setCoords(r.event->t, 1.0);
      line->setPen(QPen(red, 1.5, Qt::DashLine));
      auto* text = new QCPItemText(p);
      text->setFont(p->font());
      text->position->setTypeX(QCPItemPosition::ptPlotCoords);
      text->position->setTypeY(QCPItemPosition::ptAxisRectRatio);
      text->position->setCoords(r.event->t, 0.03);
      text->setPositionAlignment(Qt::AlignRight | Qt::AlignTop);
      text->setText(q(r.event->label) + " ");
      text->setColor(red);
      event_items_.push_back(line);
      event_items_.push_back(text);
    }
  }

  // One step line per gain entry, K[state, role], and its DARE value dashed in the same colour.
  void rebuildGainGraphs() {
    gain_->clearGraphs();
    gains_.clear();
    const ModelResult& r = *result_;
    auto steady = curve_ ? scenario_->gain(values_, data_.get()) : Expected<Metrics>(Error{""});
    int colour = 0;
    std::vector<std::string> units;
    for (const auto& ch : r.chans) {
      const std::size_t m = ch.y.size();
      for (std::size_t i = 0; i < r.n(); ++i) {
        for (std::size_t j = 0; j < m; ++j) {
          const std::string entry = "K." + r.state_keys[i] + "." + ch.roles[j];
          // Each entry in its own unit, [state]/[role], as the model declares it.
          units.push_back(describe_metric(*scenario_, entry).unit);
          const QColor c = plot::color::cycle(colour++);
          GainGraph g;
          g.k = &ch.K[i * m + j];
          g.live = plot::addGraph(gain_, plot::gainEntryLabel(entry, units.back()), c,
                                  plot::Style::kStep);
          if (steady) {
            if (auto it = steady->find(entry); it != steady->end()) {
              g.steady = plot::addGraph(gain_, "", c, plot::Style::kDashed);
              g.steady->removeFromLegend();
              g.steady_value = it->second;
            }
          }
          gains_.push_back(g);
        }
      }
    }
    gain_->yAxis->setLabel(plot::gainAxisLabel(units));
  }

  // The curve is 100 DARE solutions (≈ 10 ms for a small model): computed on a pool thread so
  // the other plots redraw at once; requests coalesce, the latest values win.
  void requestCurve() {
    if (!curve_ || curve_key_.empty()) return;
    curve_outstanding_ = true;
    if (curve_watcher_.isRunning()) {
      curve_pending_ = true;
      return;
    }
    curve_pending_ = false;
    auto s = scenario_;
    auto d = data_;
    const ParamValues v = values_;
    const std::string key = curve_key_;
    curve_watcher_.setFuture(QtConcurrent::run([s, d, v, key] {
      return std::make_shared<const Expected<GainCurve>>(gain_curve(*s, v, key, 100, d.get()));
    }));
  }

  void curveReady() {
    if (curve_pending_) {
      requestCurve();
      return;
    }
    curve_outstanding_ = false;
    const auto c = curve_watcher_.result();
    if (!c->ok()) {
      curve_->setMessage(q(c->error()));
    } else {
      const GainCurve& g = **c;
      const ParamSpec* p = scenario_->params().find(g.key);
      curve_->setCurve(g, q(p && !p->label.empty() ? p->label : g.key),
                       q(p ? p->unit : std::string()));
    }
    emit idle();
  }

  void drawUpTo(std::size_t index) {
    const ModelResult& r = *result_;
    const plot::Frame f = plot::frameAt(r.t, index);
    for (auto& s : states_)
      s->draw(f);
    for (auto& comp : components_) {
      if (comp.z_row >= r.z.size()) continue;
      plot::setSeries(comp.z, r.t, r.z[comp.z_row], f.n);
      if (comp.turn > 0.0) {
        const GappedSeries& g = comp.zhat_gapped;
        plot::setSeries(comp.zhat, g.t, g.y, g.points_for(f.n), false);
      } else {
        plot::setSeries(comp.zhat, r.t, comp.zhat_y, f.n);
      }
      plot::rescale(comp.measured, f.t0, f.t1, f.settle());
      plot::setCursorAt(comp.cursor, f.tc, !f.all);
      plot::replot(comp.measured);
      comp.innovation->draw(f);
    }
    for (auto& n : nis_)
      n->draw(f);
    for (const auto& g : gains_) {
      plot::setSeries(g.live, r.t, *g.k, f.n);
      if (g.steady) plot::setLevel(g.steady, f, g.steady_value);
    }
    plot::rescale(gain_, f.t0, f.t1, f.settle());
    plot::setCursorAt(gain_cursor_, f.tc, !f.all);
    plot::replot(gain_);
    imm_.draw(f, index);
    for (auto& b : blocks_)
      b->draw(f);
  }

  std::shared_ptr<const Scenario> scenario_;
  std::optional<ModelLayout> layout_;
  std::shared_ptr<const Dataset> data_;
  std::shared_ptr<const ModelResult> result_;
  std::vector<std::shared_ptr<const ModelResult>> ghosts_;
  ParamValues values_;
  std::size_t cursor_ = plot::kAll;
  std::vector<std::unique_ptr<plot::EstimatePlot>> states_;
  std::vector<Component> components_;
  std::vector<std::unique_ptr<plot::NisPlot>> nis_;
  QCustomPlot* gain_ = nullptr;
  QCPItemStraightLine* gain_cursor_ = nullptr;
  std::vector<GainGraph> gains_;
  ImmPanels imm_;  // a model with modes
  std::unique_ptr<plot::GainCurvePlot> curve_;
  std::vector<std::unique_ptr<plot::BlockDrawer>> blocks_;  // the file's plot blocks
  std::vector<QCustomPlot*> time_blocks_;                   // those that plot against time
  std::vector<QCPAbstractItem*> event_items_;               // the event's line and label
  std::vector<std::string> curve_keys_;
  std::string curve_key_;
  QComboBox* combo_ = nullptr;
  QFutureWatcher<std::shared_ptr<const Expected<GainCurve>>> curve_watcher_;
  bool curve_pending_ = false;
  bool curve_outstanding_ = false;
};

}  // namespace

void register_view_model(ViewRegistry& registry) {
  registry.add("model", [] { return std::make_unique<ModelView>(); });
}

}  // namespace kfw
