#include "model/model_scenario.h"

#include "model/model_filter_view.h"

#include <Eigen/Core>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "core/statistics.h"
#include "core/suggest.h"
#include "filter/angle.h"
#include "filter/consistency.h"
#include "filter/dare.h"
#include "model/imm/imm_metrics.h"
#include "model/imm/imm_spec.h"
#include "model/loop/closed_loop.h"
#include "model/loop/loop_spec.h"
#include "model/model_derived.h"
#include "model/model_eval.h"
#include "model/model_filter.h"
#include "model/model_gates.h"
#include "model/model_noise.h"
#include "model/model_spec.h"
#include "model/model_stats.h"
#include "model/model_steady.h"
#include "model/plots/model_plots.h"
#include "model/world/model_sim.h"

namespace kfw {

using nlohmann::json;
using OJson = nlohmann::ordered_json;

namespace {

// The parameters every model scenario has; a preset may declare them to change value or range.
std::vector<ParamSpec> standard_params(const std::vector<std::string>& filters,
                                       const std::string& filter) {
  const auto it = std::find(filters.begin(), filters.end(), filter);
  const double fi = it == filters.end() ? 0.0 : static_cast<double>(it - filters.begin());
  ParamSpec f{"filter",
              "filter",
              "",
              0.0,
              static_cast<double>(filters.size() - 1),
              fi,
              Scale::kChoice,
              "Filter",
              "kf: linear, Joseph form; ekf: exact symbolic Jacobians; ukf: scaled sigma points."};
  f.choices = filters;
  const std::string F = "Filter", S = "Simulator";
  std::vector<ParamSpec> ukf = {
      {"ukf.alpha", "UKF α, sigma-point spread", "", 1e-3, 1.0, 1.0, Scale::kLog, F,
       "Scaled unscented transform: λ = α²(n + κ) − n."},
      {"ukf.beta", "UKF β, prior knowledge (2: Gaussian)", "", 0.0, 4.0, 2.0, Scale::kLinear, F,
       "Adds (1 − α² + β) to the central covariance weight.", 2},
      {"ukf.kappa", "UKF κ, secondary scaling", "", -5.0, 10.0, 0.0, Scale::kLinear, F,
       "n + κ scales the sigma points (n + λ must stay positive).", 2}};
  for (auto& u : ukf) {
    u.shown_with = "filter";
    u.shown_for = {"ukf"};
  }
  return {
      f,
      ukf[0],
      ukf[1],
      ukf[2],
      {"sim.seed", "seed", "", 0, 1e6, 1, Scale::kInteger, S, "Random seed of the simulator."},
      {"sim.duration", "duration", "s", 0.01, 1e6, 60, Scale::kLinear, S, "Length of the run.", 1},
      {"sim.dt", "sample interval", "s", 1e-6, 100, 0.01, Scale::kLog, S,
       "Time step of the simulated data.", 4},
  };
}

// True when a unit needs parentheses as one side of a ratio ("m/s", "m s⁻¹"; not "m²", "(m/s)²").
bool compound_unit(const std::string& u) {
  int depth = 0;
  for (char c : u) {
    if (c == '(') ++depth;
    if (c == ')') --depth;
    // '\xB7' ends the UTF-8 of '·' (a product, "N·m").
    if (depth == 0 && (c == '/' || c == '*' || c == ' ' || c == '\xB7')) return true;
  }
  return false;
}

std::string ratio_side(const std::string& u) {
  return compound_unit(u) ? "(" + u + ")" : u;
}

// The unit of a ratio num/den as a reader writes it: "" when they cancel (m/m), "1/s" for
// (m/s)/m, "s" for m/(m/s), "m/rad" otherwise.
std::string unit_ratio(const std::string& num, const std::string& den) {
  if (num == den) return "";
  if (den.empty()) return num;
  if (num.empty()) return "1/" + ratio_side(den);
  if (num.rfind(den + "/", 0) == 0) return "1/" + ratio_side(num.substr(den.size() + 1));
  if (den.rfind(num + "/", 0) == 0) return den.substr(num.size() + 1);
  return ratio_side(num) + "/" + ratio_side(den);
}

// The identifiers an expression names (numbers, operators and functions' parentheses skipped).
void collect_names(const std::string& text, std::set<std::string>& out) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (std::isalpha(c) || c == '_') {
      std::size_t j = i + 1;
      while (j < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_'))
        ++j;
      out.insert(text.substr(i, j - i));
      i = j;
    } else if (std::isdigit(c) || c == '.') {
      // A number, exponent included ("1.5e-3" must not yield "e").
      ++i;
      while (i < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '.'))
        ++i;
    } else {
      ++i;
    }
  }
}

// The names the model's noise covariances use: Q (or Qc and G) and every channel's R.
std::set<std::string> noise_names(const model::ModelSpec& s) {
  std::set<std::string> names;
  auto add = [&](const model::MatrixSpec& m) {
    for (const auto& e : m.e)
      collect_names(e.text, names);
  };
  add(s.process.Q);
  add(s.process.Qc);
  add(s.process.G);
  for (const auto& c : s.channels)
    add(c.R);
  return names;
}

class ModelScenario final : public Scenario {
 public:
  ModelScenario(std::shared_ptr<const model::ModelSpec> spec, ParamTable table, std::string title)
      : spec_(std::move(spec)), table_(std::move(table)), title_(std::move(title)) {}

  std::string name() const override { return "model"; }
  std::string title() const override { return title_; }
  const ParamTable& params() const override { return table_; }
  // One primary state: finalize_run takes rmse from it; several: run_impl sets it.
  std::string primary_state() const override {
    return spec_->primary.size() == 1 ? spec_->primary.front() : std::string();
  }
  const std::shared_ptr<const model::ModelSpec>& spec() const { return spec_; }
  Expected<ModelFilterView> filter_view(const ParamValues& checked) const {
    if (auto st = params().check(checked); !st) return st.err();
    ModelFilterView view{spec_, with_mode_params(checked), {}};
    auto o = options(view.values);
    if (!o) return o.err();
    view.options = *o;
    return view;
  }

  std::vector<ColumnSpec> columns() const override {
    std::vector<ColumnSpec> c{{"t", "s", "time", true}};
    for (const auto& in : spec_->inputs)
      c.push_back({in.name, in.unit, "input " + in.label, true});
    for (const auto& ch : spec_->channels) {
      for (const auto& r : ch.roles)
        c.push_back({r.name, r.unit, "channel " + ch.label + "; empty = no sample", true});
    }
    std::set<std::string> seen;
    for (const auto& x : c)
      seen.insert(x.name);
    for (std::size_t i = 0; i < spec_->truth.size(); ++i) {
      const auto& col = spec_->truth[i];
      if (!col.empty() && seen.insert(col).second) {
        c.push_back({col, spec_->states[i].unit,
                     "true " + spec_->states[i].label + "; empty where unknown", false});
      }
    }
    for (const auto& x0 : spec_->x0) {
      if (!x0.first_column.empty() && seen.insert(x0.first_column).second) {
        c.push_back({x0.first_column, "", "initial state from its first sample", false});
      }
    }
    return c;
  }

  std::vector<MetricSpec> metric_specs() const override {
    std::vector<MetricSpec> out = model::gate_metric_specs(*spec_);
    for (const auto& c : spec_->channels) {
      // A channel of several components is tested for whiteness component by component.
      if (c.comps.size() > 1) {
        for (const auto& r : c.comps) {
          out.push_back({"whiteness_p." + c.name + "." + r.name,
                         "whiteness p of " + c.label + ": " + r.name, "",
                         "Ljung–Box p-value (20 lags) of " + r.name + "'s innovation over √S (" +
                             r.name + "'s diagonal entry), at the channel's own rate",
                         MetricGroup::kConsistency, Direction::kHigher, 0.0, 0.01, 1.0});
        }
      }
    }
    // The gain entries (`gain`'s steady state, the gains plot over time): [state]/[role].
    for (const auto& st : spec_->states) {
      for (const auto& c : spec_->channels) {
        for (const auto& r : c.comps) {
          out.push_back({"K." + st.name + "." + r.name, "gain of " + st.name + " from " + r.name,
                         unit_ratio(st.unit, r.unit),
                         "Kalman gain entry: the change of " + st.name + "'s estimate per " +
                             "unit of " + r.name + "'s innovation (kfw-cli gain: its DARE " +
                             "steady state, for a linear time-invariant model)",
                         MetricGroup::kGains, Direction::kNone});
        }
      }
    }
    for (auto& d : model::stat_metric_specs(*spec_))
      out.push_back(std::move(d));
    for (auto& d : model::derived_metric_specs(*spec_))
      out.push_back(std::move(d));
    for (auto& d : model::imm_metric_specs(*spec_))
      out.push_back(std::move(d));
    for (auto& d : model::loop_metric_specs(*spec_))
      out.push_back(std::move(d));
    return out;
  }

  // The simulator already draws x0 ~ N(x0, P0); the filter's prior mean becomes the x0
  // expressions (a `first` sample would make the prior depend on the simulated data).
  // Not where a world simulates the truth and the filter starts at a channel's first sample
  // (`{"first": "CHANNEL.COMPONENT"}`, seed 001): the world's initial state is its own, and the
  // filter has no x0 expressions to draw it from.
  std::shared_ptr<const Scenario> with_x0_from_prior() const override {
    if (spec_->world && spec_->start_channel >= 0) {
      return nullptr;
    }
    auto spec = std::make_shared<model::ModelSpec>(*spec_);
    for (auto& x0 : spec->x0)
      x0.first_column.clear();
    return std::make_shared<ModelScenario>(std::move(spec), table_, title_);
  }

  // A closed loop does not filter a loaded log: each run simulates the world with the controller.
  std::optional<DataUnused> data_unused(const ParamValues& v) const override {
    if (!closed(v)) return std::nullopt;
    const model::ControllerSpec& c = *spec_->controller;
    std::string fix;
    if (!c.loop_param.empty()) {
      const ParamSpec* p = table_.find(c.loop_param);
      for (std::size_t i = 0; p && i < c.closed_by_choice.size(); ++i) {
        if (!c.closed_by_choice[i]) {
          fix = c.loop_param + "=" + p->choices[i];
          break;
        }
      }
    }
    return DataUnused{"the loop is closed: each run simulates the world with the controller (" +
                          (c.loop_param.empty() ? std::string("model.controller") : c.loop_param) +
                          ")",
                      fix};
  }

  Expected<Dataset> simulate(const ParamValues& v) const override {
    if (auto st = params().check(v); !st) return st.err();
    if (closed(v)) {
      auto o = options(with_mode_params(v));
      if (!o) return o.err();
      auto loop = model::run_closed_loop(*spec_, v, *o, {}, "model '" + title_ + "'");
      if (!loop) return loop.err();
      return std::move(loop->data);
    }
    // A world block generates the data; without one the model simulates itself.
    return model::simulate_model(spec_->world ? *spec_->world : *spec_, with_mode_params(v),
                                 "model '" + title_ + "'");
  }

  Expected<Metrics> gain(const ParamValues& v, const Dataset* data) const override;

  // The file's noise_param keys (model_noise.h).
  std::vector<NoiseLink> noise_links() const override { return model::noise_links(spec_, table_); }

  // The commands the file has blocks for (model_stats.h).
  std::vector<std::string> commands() const override {
    std::vector<std::string> out;
    for (const auto& c : model::model_commands()) {
      if (model::model_offers(*spec_, c)) out.push_back(c);
    }
    return out;
  }
  Expected<std::string> command(const std::string& cmd, const Dataset& d,
                                const ParamValues& v) const override {
    if (!model::model_offers(*spec_, cmd)) return Scenario::command(cmd, d, v);
    auto r = run(d, v);
    if (!r) return r.err();
    const auto* res = dynamic_cast<const model::ModelResult*>(r->get());
    if (!res) return Error{"stats: the run is not a model run"};
    return model::stats_json(*spec_, *res, d.source);
  }

 protected:
  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& checked,
                                                const RunControl& control) const override {
    if (auto st = params().check(checked); !st) return st.err();
    const ParamValues v = with_mode_params(checked);
    auto o = options(v);
    if (!o) return o.err();
    std::shared_ptr<model::ModelResult> r;
    model::LoopRun loop;
    if (closed(v)) {
      auto run = model::run_loop_model(*spec_, v, *o, control, "model '" + title_ + "'");
      if (!run) return run.err();
      loop = std::move(*run);
      r = loop.result;
    } else {
      if (auto st = require_columns(d, columns()); !st) return st.err();
      auto run = model::run_model_filter(*spec_, d, v, *o, control);
      if (!run) return run.err();
      r = std::move(*run);
      if (spec_->controller) {
        if (auto st = model::replay_events(*spec_, v, d, *r); !st) return st.err();
      }
    }
    return finish(closed(v) ? loop.data : d, v, std::move(r));
  }

 private:
  bool closed(const ParamValues& v) const {
    return spec_->controller && model::loop_closed(*spec_->controller, v);
  }

  Expected<model::FilterOptions> options(const ParamValues& v) const {
    model::FilterOptions o;
    auto kind = model::filter_kind(table_.format("filter", param(v, "filter")));
    if (!kind) return kind.err();
    o.kind = *kind;
    o.alpha = param(v, "ukf.alpha");
    o.beta = param(v, "ukf.beta");
    o.kappa = param(v, "ukf.kappa");
    return o;
  }

  // The metrics of a run over `d` (the log, or the closed loop's own data).
  Expected<std::shared_ptr<RunResult>> finish(const Dataset& d, const ParamValues& v,
                                              std::shared_ptr<model::ModelResult> r) const {
    model::ModelResult& res = *r;
    Metrics& m = res.metrics;
    double at = 0.0;  // model.metrics_from: the accuracy and consistency metrics start there
    const std::size_t from = model::metrics_from_row(*spec_, v, res.t, at);
    if (from >= res.steps() && from > 0) {
      ends_before(res, at);
    } else {
      state_rmse(res, from);
      if (spec_->primary.size() > 1) primary_rmse(res, from);
    }
    model::add_gate_metrics(*spec_, res, m, res.undefined);
    model::add_imm_metrics(*spec_, d, res);
    if (from > 0 && from < res.steps()) {
      add_consistency_metrics(model::channels_from(res.channels(), from),
                              model::nees_from(res.nees_series(), from), m, res.undefined);
    } else if (from == 0) {
      add_consistency_metrics(res.channels(), res.nees_series(), m, res.undefined);
    }
    if (auto st = model::add_derived(*spec_, v, d, res, &derived_cache_); !st) return st.err();
    model::add_stat_metrics(*spec_, v, res);
    const double dt = d.rows() >= 2 ? d.median_dt() : param(v, spec_->sim_dt_key);
    if (auto st = model::add_plot_points(*spec_, v, dt, res); !st) return st.err();
    return std::shared_ptr<RunResult>(std::move(r));
  }

  // The values with the grid's mode parameters (no slider) at their grid's centre.
  ParamValues with_mode_params(const ParamValues& v) const {
    if (spec_->mode_params.empty() || !spec_->modes) return v;
    ParamValues all = v;
    spec_->modes->set_mode_params(*spec_, all);
    return all;
  }

  // rmse.<state> from row `from`: an angle state's from the wrapped error (the shared one would
  // not wrap); with model.metrics_from every state's here (the shared one counts every row).
  void state_rmse(model::ModelResult& res, std::size_t from) const {
    for (std::size_t i = 0; i < res.n(); ++i) {
      const Angle a = spec_->states[i].angle;
      if ((a == Angle::kNone && from == 0) || res.truth[i].empty()) continue;
      std::vector<double> e(res.steps() - from, kNoSample), zero(res.steps() - from, 0.0);
      for (std::size_t k = from; k < res.steps(); ++k)
        e[k - from] = wrap(res.x[i][k] - res.truth[i][k], a);
      res.metrics["rmse." + spec_->states[i].name] = rmse_finite(e, zero);
    }
  }

  // A run that ends before model.metrics_from: its accuracy and consistency metrics say so.
  void ends_before(model::ModelResult& res, double at) const {
    const std::string why =
        "the run ends before t = " + model::number(at) + " s (model.metrics_from)";
    res.undefined.emplace("rmse", why);
    for (const auto& st : spec_->states)
      res.undefined.emplace("rmse." + st.name, why);
    for (const char* k :
         {"nis_mean", "nis_in_bounds", "nll", "whiteness_p", "nees_mean", "nees_in_bounds"})
      res.undefined.emplace(k, why);
  }

  // `rmse` of several primary states: sqrt(mean over the steps of Σ err_i²), angles wrapped,
  // over the steps from `from` where every one has an estimate and a truth value.
  void primary_rmse(model::ModelResult& res, std::size_t from) const {
    std::vector<std::size_t> idx;
    for (const auto& name : spec_->primary) {
      const auto i = static_cast<std::size_t>(spec_->state_index(name));
      if (res.truth[i].empty()) {
        res.undefined.emplace("rmse", "no truth for the primary state '" + name + "' in the data");
        return;
      }
      idx.push_back(i);
    }
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t k = from; k < res.steps(); ++k) {
      double e2 = 0.0;
      for (std::size_t i : idx) {
        const double e = wrap(res.x[i][k] - res.truth[i][k], spec_->states[i].angle);
        e2 += e * e;
      }
      if (!std::isfinite(e2)) continue;
      sum += e2;
      ++count;
    }
    res.metrics["rmse"] = count ? std::sqrt(sum / static_cast<double>(count))
                                : std::numeric_limits<double>::quiet_NaN();
  }

  // The derived scalars at v and dt, from a pool of compiled evaluators (gain() runs on several
  // threads at once, and a gain curve calls it at every point: compiling each time cost ≈ 0.25 ms
  // a call, 27 ms of CPU per slider change on the helicopter file).
  Metrics derived_scalars(const ParamValues& v, double dt) const {
    if (spec_->derived.empty()) return {};
    std::unique_ptr<model::DerivedScalars> e;
    {
      std::lock_guard lock(derived_mu_);
      if (!derived_pool_.empty()) {
        e = std::move(derived_pool_.back());
        derived_pool_.pop_back();
      }
    }
    if (!e) e = std::make_unique<model::DerivedScalars>(*spec_);
    Metrics out = e->eval(v, dt);
    std::lock_guard lock(derived_mu_);
    derived_pool_.push_back(std::move(e));
    return out;
  }

  std::shared_ptr<const model::ModelSpec> spec_;
  ParamTable table_;
  std::string title_;
  mutable std::mutex derived_mu_;
  mutable std::vector<std::unique_ptr<model::DerivedScalars>> derived_pool_;
  mutable model::DerivedCache derived_cache_;  // series that read no estimate, between runs
};

Expected<Metrics> ModelScenario::gain(const ParamValues& checked, const Dataset* data) const {
  if (auto st = params().check(checked); !st) return st.err();
  const ParamValues v = with_mode_params(checked);
  const model::ModelSpec& s = *spec_;
  if (!s.time_invariant()) {
    return Error{s.path + ": no steady-state gain: the model is not linear time-invariant (F, B, " +
                 "Q, H and R must depend on parameters and dt only)"};
  }
  const double dt = data && data->rows() >= 2 ? data->median_dt() : param(v, s.sim_dt_key);
  auto ev = model::ModelEval::create(s, v);
  if (!ev) return ev.err();
  const std::string where =
      data && data->rows() >= 2 ? "the median interval of " + data->source : s.sim_dt_key;
  if (auto st = (*ev)->check_dt(dt, where); !st) return st.err();
  auto steady = model::model_steady_state(s, **ev);
  if (!steady) return steady.err();
  const SteadyState* ss = &steady->dare;
  const std::vector<std::string>& roles = steady->roles;
  const Eigen::Index n = s.n(), rows = static_cast<Eigen::Index>(roles.size());
  const int every = steady->every;
  Metrics g = derived_scalars(v, dt);  // β and the like: a gain curve's other axis
  g["dt"] = dt;
  g["every"] = every;
  g["dare_iterations"] = ss->iterations;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::string& si = s.states[static_cast<std::size_t>(i)].name;
    for (Eigen::Index j = 0; j < rows; ++j)
      g["K." + si + "." + roles[static_cast<std::size_t>(j)]] = ss->K(i, j);
    for (Eigen::Index j = i; j < n; ++j) {
      const std::string suffix =
          i == j ? si : si + "." + s.states[static_cast<std::size_t>(j)].name;
      g["P_pred." + suffix] = ss->P_pred(i, j);
      g["P_post." + suffix] = ss->P_post(i, j);
    }
  }
  return g;
}

}  // namespace

Expected<ModelFilterView> model_filter_view(const Scenario& s, const ParamValues& values) {
  const auto* m = dynamic_cast<const ModelScenario*>(&s);
  if (!m) return Error{"scenario '" + s.name() + "' is not a model file"};
  return m->filter_view(values);
}

std::optional<ModelLayout> model_layout_of(const Scenario& s) {
  const auto* m = dynamic_cast<const ModelScenario*>(&s);
  if (!m) return std::nullopt;
  ModelLayout l;
  // An angle's full turn (wrap() keeps it within half a turn of zero).
  auto turn = [](Angle a) {
    return a == Angle::kRad ? 2.0 * std::numbers::pi : a == Angle::kDeg ? 360.0 : 0.0;
  };
  for (const auto& st : m->spec()->states)
    l.states.push_back({st.name, st.label.empty() ? st.name : st.label, st.unit, turn(st.angle)});
  for (const auto& c : m->spec()->channels) {
    ModelLayout::Channel ch{c.name, c.label.empty() ? c.name : c.label, {}};
    for (const auto& r : c.comps)
      ch.roles.push_back({r.name, r.unit, r.angle != Angle::kNone, turn(r.angle)});
    l.channels.push_back(std::move(ch));
  }
  l.time_invariant = m->spec()->time_invariant();
  l.modes = m->spec()->modes != nullptr;
  if (l.modes) {
    for (const auto& a : m->spec()->modes->grid)
      l.grid.push_back({a.param, a.label, a.unit});
  }
  l.plots = m->spec()->plots;
  l.first_panels = m->spec()->first_panels;
  l.panels = model::panel_names(*m->spec());
  return l;
}

Expected<std::unique_ptr<Scenario>> make_model_scenario(const OJson& preset,
                                                        const std::string& path) {
  if (!preset.is_object()) return Error{path + ": a preset must be a JSON object"};
  if (preset.value("scenario", std::string()) != "model") {
    return Error{path + ": scenario: expected \"model\""};
  }
  std::string title = "model";
  if (auto it = preset.find("title"); it != preset.end() && it->is_string()) title = *it;
  // `filter` is declared by the model's linearity (kf only for linear models): read apart.
  OJson params = preset.value("parameters", OJson());
  OJson filter_entry;
  std::size_t filter_place = 0;  // where the file declares it, among its parameters
  if (params.is_object() && params.contains("filter")) {
    for (auto it = params.begin(); it != params.end() && it.key() != "filter"; ++it)
      ++filter_place;
    filter_entry = params["filter"];
    params.erase("filter");
  }
  auto declared = parse_param_table(params, path);
  if (!declared) return declared.err();
  if (!preset.contains("model")) return Error{path + ": missing key 'model'"};
  auto spec = model::parse_model(json(preset["model"]), *declared, path);
  if (!spec) return spec.err();
  // Named metrics in the file's order (the parse sorts an object's keys), as parameters are.
  if (const auto& m = preset["model"]; m.contains("metrics") && m["metrics"].is_object()) {
    std::vector<std::string> order;
    for (const auto& [key, value] : m["metrics"].items())
      order.push_back(key);
    const auto at = [&](const model::StatMetricSpec& s) {
      return std::find(order.begin(), order.end(), s.name) - order.begin();
    };
    std::stable_sort(spec->stat_metrics.begin(), spec->stat_metrics.end(),
                     [&](const auto& a, const auto& b) { return at(a) < at(b); });
  }

  auto filters = model::filter_choices(*spec);
  // A preset may offer some of them, in its own order (seed 003's kf and steady).
  if (filter_entry.is_object() && filter_entry.contains("choices")) {
    const OJson& c = filter_entry["choices"];
    std::vector<std::string> own;
    for (std::size_t i = 0; c.is_array() && i < c.size(); ++i) {
      const std::string name = c[i].is_string() ? c[i].get<std::string>() : std::string();
      if (std::find(filters.begin(), filters.end(), name) == filters.end() ||
          std::find(own.begin(), own.end(), name) != own.end()) {
        return Error{path + ": parameters.filter.choices[" + std::to_string(i) + "]: '" + name +
                     "' is not a filter for this model, or repeated (" +
                     [&] {
                       std::string all;
                       for (const auto& f : filters)
                         all += (all.empty() ? "" : ", ") + f;
                       return all;
                     }() +
                     ")"};
      }
      own.push_back(name);
    }
    if (!c.is_array() || own.empty()) {
      return Error{path + ": parameters.filter.choices: expected a list of filter names"};
    }
    filters = std::move(own);
  }
  std::string filter = spec->filter;
  if (std::find(filters.begin(), filters.end(), filter) == filters.end()) filter = filters.front();
  if (!filter_entry.is_null()) {
    const OJson v = filter_entry.is_object() ? filter_entry.value("value", OJson()) : filter_entry;
    if (v.is_string()) {
      filter = v.get<std::string>();
    } else if (v.is_number() && v.get<double>() >= 0.0 &&
               v.get<double>() < static_cast<double>(filters.size()) &&
               v.get<double>() == std::floor(v.get<double>())) {
      // The choice's index, as preset_to_json writes it (0.0 as well as 0).
      filter = filters[static_cast<std::size_t>(v.get<double>())];
    } else {
      return Error{path + ": parameters.filter.value: expected a filter name (kf, ekf, ukf)"};
    }
    if (std::find(filters.begin(), filters.end(), filter) == filters.end()) {
      return Error{path + ": parameters.filter.value: '" + filter +
                   "' is not a filter for this model (" + (spec->linear() ? "kf, " : "") +
                   "ekf, ukf" + (spec->linear() ? "" : "; kf needs F and H") + ")"};
    }
  }
  std::vector<ParamSpec> specs = declared->specs();
  // A file that marks no parameter tunable (no entry has "tunable") is tuned over the parameters
  // its noise uses, Q (or Qc, G) and R: what an engineer tunes first. Log-scale ones are searched
  // in log10 (experiment/tuning.h).
  bool marks = false;
  if (params.is_object()) {
    for (const auto& e : params) {
      marks = marks || (e.is_object() && e.contains("tunable"));
    }
  }
  if (!marks) {
    const auto noise = noise_names(*spec);
    for (auto& p : specs) {
      const bool continuous = p.scale == Scale::kLinear || p.scale == Scale::kLog;
      if (continuous && p.min < p.max && noise.count(p.key)) p.tunable = true;
    }
  }
  std::vector<ParamSpec> all;
  for (auto& s : standard_params(filters, filter)) {
    if (s.key == "filter" && !filter_entry.is_null()) {
      specs.insert(specs.begin() + static_cast<std::ptrdiff_t>(filter_place), s);
    } else if (s.key == "sim.dt" && spec->sim_dt_key != "sim.dt") {
      continue;  // the file names its own simulation step
    } else if (s.key == "filter" || !declared->find(s.key)) {
      all.push_back(s);
    }
  }
  // Declared parameters first (the model's own, in the file's order), then those the modes
  // gain (grid.PARAM.min, markov.stay, …), then the standard ones.
  if (spec->modes) {
    for (const auto& g : spec->modes->gained) {
      if (!declared->find(g.key)) specs.push_back(g);
    }
  }
  specs.insert(specs.end(), all.begin(), all.end());
  ParamTable table(std::move(specs));
  auto shared = std::make_shared<const model::ModelSpec>(std::move(*spec));
  // P0, Q, R and Qc that depend on parameters only must be PSD at the preset's values, and a Q
  // or R that depends on dt at sim.dt.
  ParamValues defaults = table.defaults();
  if (shared->modes) shared->modes->set_mode_params(*shared, defaults);
  auto ev = model::ModelEval::create(*shared, defaults);
  if (!ev) return ev.err();
  if (shared->world) {
    auto wev = model::ModelEval::create(*shared->world, table.defaults());
    if (!wev) return wev.err();
  }
  // Every mode at the preset's values: a grid's axes, a mode's P0, Q and R (exit 2 at load).
  if (shared->modes) {
    auto modes = shared->modes->modes(*shared, defaults);
    if (!modes) return modes.err();
    for (const auto& mode : *modes) {
      auto mev = model::ModelEval::create(*mode.model, mode.values);
      if (!mev) return Error{mev.error() + " (in mode '" + mode.name + "')"};
    }
  }
  if (auto st = (*ev)->check_dt(param(defaults, shared->sim_dt_key), shared->sim_dt_key); !st) {
    return st.err();
  }
  return std::unique_ptr<Scenario>(
      std::make_unique<ModelScenario>(std::move(shared), std::move(table), std::move(title)));
}

// Registered through the generated list (engine/CMakeLists.txt), like the compiled scenarios: a
// preset whose "scenario" is "model" is built from its own "model" and "parameters" blocks.
void register_scenario_model(ScenarioRegistry& registry) {
  registry.add_from_preset("model", &make_model_scenario);
}

}  // namespace kfw
