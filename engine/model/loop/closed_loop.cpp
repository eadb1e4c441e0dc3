#include "model/loop/closed_loop.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <sstream>

#include "model/loop/loop_spec.h"
#include "model/model_eval.h"
#include "model/model_filter_detail.h"
#include "model/world/simulation.h"

namespace kfw::model {

namespace {

std::string at_row(const Dataset& d, std::size_t k) {
  std::ostringstream os;
  os << "step " << k << " (t = " << d.columns[0][k] << " s)";
  return os.str();
}

// The controller between the filter and the world, row by row (detail::LoopHook).
class Loop final : public detail::LoopHook {
 public:
  Loop(const ModelSpec& spec, detail::Simulation& sim, Dataset& d, const RunControl& control)
      : spec_(spec), c_(*spec.controller), sim_(sim), d_(d), control_(control) {}

  // The parameters, the saturation limits, the states' x0, the groups bound; the columns looked
  // up (every column added before).
  Status setup(const ParamValues& values) {
    vars_.assign(c_.symbols.names.size(), 0.0);
    for (std::size_t i = 0; i < c_.param_slots.size(); ++i)
      vars_[static_cast<std::size_t>(c_.param_slots[i])] = param(values, c_.param_keys[i]);
    ExprGroup once;
    lo_.assign(c_.outputs.size(), 0.0);
    hi_.assign(c_.outputs.size(), 0.0);
    raw_.assign(c_.outputs.size(), 0.0);
    std::vector<double> x0(c_.states.size(), 0.0);
    for (std::size_t o = 0; o < c_.outputs.size(); ++o) {
      once.add(c_.outputs[o].lo.text, &lo_[o]);
      once.add(c_.outputs[o].hi.text, &hi_[o]);
      outs_.add(c_.outputs[o].e.text, &raw_[o]);
      out_col_.push_back(&d_.columns[static_cast<std::size_t>(d_.index(c_.outputs[o].name))]);
    }
    next_vals_.assign(c_.states.size(), 0.0);
    for (std::size_t s = 0; s < c_.states.size(); ++s) {
      once.add(c_.states[s].x0.text, &x0[s]);
      next_.add(c_.states[s].next.text, &next_vals_[s]);
    }
    if (!c_.reference_name.empty()) {
      ref_.add(c_.reference.text, &ref_value_);
      ref_col_ = &d_.columns[static_cast<std::size_t>(d_.index(c_.reference_name))];
    }
    for (ExprGroup* g : {&once, &outs_, &next_, &ref_}) {
      if (auto st = g->bind(c_.symbols, vars_.data()); !st) return st;
    }
    once.eval();
    for (std::size_t o = 0; o < c_.outputs.size(); ++o) {
      if (!(lo_[o] <= hi_[o])) {
        return Error{spec_.path + ": model.controller.outputs." + c_.outputs[o].name +
                     ": min is above max at the parameters' values"};
      }
    }
    for (std::size_t s = 0; s < c_.states.size(); ++s)
      vars_[static_cast<std::size_t>(c_.states[s].slot)] = x0[s];
    held_.assign(c_.columns.size(), 0.0);
    for (const auto& col : c_.columns)
      cols_.push_back(&d_.col(col.name));
    return Ok{};
  }

  Status before(std::size_t k, bool& stop) override {
    if (k == 0) return Ok{};  // made before the filter's preparation
    if ((k & 1023) == 0 && control_.cancelled()) return Error{"cancelled"};
    if (auto st = sim_.row(k, d_); !st) return st;
    event = sim_.event_now(sim_.row_time(k));
    stop = event >= 0;
    return Ok{};
  }

  Status after(std::size_t k, const double* x, const double* P) override {
    const auto& t = d_.columns[0];
    const std::size_t n = spec_.states.size();
    vars_[static_cast<std::size_t>(c_.t_slot)] = t[k];
    vars_[static_cast<std::size_t>(c_.dt_slot)] = k > 0 ? t[k] - t[k - 1] : t[1] - t[0];
    for (std::size_t i = 0; i < n; ++i) {
      vars_[static_cast<std::size_t>(c_.estimate_slots[i])] = x[i];
      vars_[static_cast<std::size_t>(c_.variance_slots[i])] = P[i * n + i];
    }
    for (std::size_t j = 0; j < cols_.size(); ++j) {
      const double v = (*cols_[j])[k];
      if (std::isfinite(v)) held_[j] = v;  // a sensor without a sample here: its last one
      vars_[static_cast<std::size_t>(c_.columns[j].slot)] = held_[j];
    }
    if (ref_col_) {
      ref_.eval();
      vars_[static_cast<std::size_t>(c_.reference_slot)] = ref_value_;
      (*ref_col_)[k] = ref_value_;
    }
    outs_.eval();
    for (std::size_t o = 0; o < c_.outputs.size(); ++o) {
      const double v = std::clamp(raw_[o], lo_[o], hi_[o]);
      if (!std::isfinite(raw_[o])) {
        return failure(at_row(d_, k) + ": the controller's output '" + c_.outputs[o].name +
                       "' (model.controller.outputs." + c_.outputs[o].name +
                       ") is not finite; the run stops here");
      }
      vars_[static_cast<std::size_t>(c_.outputs[o].slot)] = v;
      (*out_col_[o])[k] = v;
      sim_.drive(static_cast<std::size_t>(c_.outputs[o].world_input), v);
    }
    next_.eval();
    for (std::size_t s = 0; s < c_.states.size(); ++s) {
      if (!std::isfinite(next_vals_[s])) {
        return failure(at_row(d_, k) + ": the controller's state '" + c_.states[s].name +
                       "' (model.controller.states." + c_.states[s].name +
                       ".next) is not finite; the run stops here");
      }
      vars_[static_cast<std::size_t>(c_.states[s].slot)] = next_vals_[s];
    }
    return Ok{};
  }

  int event = -1;

 private:
  const ModelSpec& spec_;
  const ControllerSpec& c_;
  detail::Simulation& sim_;
  Dataset& d_;
  const RunControl& control_;
  std::vector<double> vars_, lo_, hi_, raw_, next_vals_, held_;
  double ref_value_ = 0.0;
  ExprGroup outs_, next_, ref_;
  std::vector<std::vector<double>*> out_col_;
  std::vector<double>* ref_col_ = nullptr;
  std::vector<const std::vector<double>*> cols_;
};

void keep(std::vector<double>& v, std::size_t n) {
  if (v.size() > n) v.resize(n);
}

// The copies the preparation made of the data (then still empty past row 0), taken again.
void copy_columns(const ModelSpec& spec, const detail::Data& data, ModelResult& r) {
  std::size_t role = 0;
  for (std::size_t c = 0; c < spec.channels.size(); ++c) {
    for (std::size_t j = 0; j < data.z[c].size(); ++j, ++role) {
      if (!spec.channels[c].preprocessed()) r.z[role] = *data.z[c][j];
    }
  }
  for (std::size_t i = 0; i < data.truth.size(); ++i) {
    if (data.truth[i]) r.truth[i] = *data.truth[i];
  }
}

}  // namespace

void truncate_result(ModelResult& r, std::size_t n) {
  keep(r.t, n);
  for (auto* group : {&r.x, &r.P, &r.truth, &r.z, &r.derived}) {
    for (auto& v : *group)
      keep(v, n);
  }
  keep(r.nees, n);
  for (auto& [name, v] : r.loop_columns)
    keep(v, n);
  for (auto& c : r.chans) {
    for (auto* group : {&c.y, &c.S, &c.K}) {
      for (auto& v : *group)
        keep(v, n);
    }
    for (auto* v : {&c.nis, &c.log_det_s, &c.nll, &c.outlier})
      keep(*v, n);
    std::erase_if(c.gated_rows, [n](std::size_t k) { return k >= n; });
  }
}

Expected<LoopRun> run_closed_loop(const ModelSpec& spec, const ParamValues& values,
                                  const FilterOptions& options, const RunControl& control,
                                  const std::string& name, bool quiet) {
  const ControllerSpec& c = *spec.controller;
  auto prepared = detail::prepare_simulation(*spec.world, values, name, quiet);
  if (!prepared) return prepared.err();
  detail::Simulation& sim = *prepared->sim;
  LoopRun out;
  Dataset& d = out.data;
  if (auto st = sim.begin(d, prepared->source); !st) return st.err();
  const std::size_t rows = d.rows();
  if (!c.reference_name.empty() && !d.has(c.reference_name)) d.add(c.reference_name, rows);
  if (auto st = sim.row(0, d); !st) return st.err();
  if (const int e = sim.event_now(sim.row_time(0)); e >= 0) {
    return Error{spec.path + ": model.world.events." + spec.world->events[e].name +
                 ": holds at t = 0, before the first row (the run has no row)"};
  }
  Loop loop(spec, sim, d, control);
  if (auto st = loop.setup(values); !st) return st.err();
  auto p = detail::prepare_run(spec, d, values, options, control);
  if (!p) return p.err();
  if (auto st = detail::run_prepared(**p, values, d, &loop); !st) return st.err();
  detail::Context& ctx = *(*p)->ctx;
  const std::size_t end = ctx.end;
  for (auto& col : d.columns)
    keep(col, end);
  ModelResult& r = *(*p)->r;
  copy_columns(spec, (*p)->data, r);
  truncate_result(r, end);
  for (auto& ch : r.chans) {
    const std::string& col = spec.channels[&ch - r.chans.data()].outlier_column;
    if (!col.empty() && d.has(col)) ch.outlier = d.col(col);
  }
  if (auto done = detail::finish_run(ctx); !done) return done.err();
  if (!c.reference_name.empty())
    r.loop_columns.emplace_back(c.reference_name, d.col(c.reference_name));
  for (const auto& o : c.outputs)
    r.loop_columns.emplace_back(o.name, d.col(o.name));
  out.event = loop.event;
  if (loop.event >= 0) {
    out.event_t = sim.row_time(end);
    const EventSpec& ev = spec.world->events[static_cast<std::size_t>(loop.event)];
    r.event = ModelResult::LoopEvent{ev.name, ev.label, out.event_t};
  }
  for (std::size_t e = 0; e < spec.world->events.size(); ++e) {
    const double at = sim.first_at(e);
    out.first_at.push_back(at < out.event_t || std::isnan(out.event_t) ? at : kNoSample);
  }
  for (std::size_t s = 0; s < spec.world->channels.size(); ++s) {
    out.impulsive.push_back(sim.impulsive(s));
    out.sampled.push_back(sim.sampled(s));
  }
  out.result = (*p)->r;
  return out;
}

Expected<LoopRun> run_loop_model(const ModelSpec& spec, const ParamValues& values,
                                 const FilterOptions& options, const RunControl& control,
                                 const std::string& name) {
  const ControllerSpec& c = *spec.controller;
  // The noise-free twin on a thread of its own: a slider move waits for the longer loop only.
  std::future<Expected<LoopRun>> twin;
  if (!c.noise_free.empty()) {
    twin = std::async(std::launch::async,
                      [&] { return run_closed_loop(spec, values, options, control, name, true); });
  }
  auto run = run_closed_loop(spec, values, options, control, name, false);
  if (twin.valid()) twin.wait();
  if (!run) return run.err();
  ModelResult& r = *run->result;
  const std::size_t rows = run->data.rows();
  if (twin.valid()) {
    auto quiet = twin.get();
    if (!quiet) return Error{quiet.error() + " (in the noise-free loop)", quiet.exit_code()};
    for (const auto& [col, from] : c.noise_free) {
      std::vector<double> v = quiet->data.col(from);
      v.resize(rows, kNoSample);  // the noise-free run may end earlier (its own event)
      run->data.add(col, rows) = v;
      r.loop_columns.emplace_back(col, std::move(v));
    }
  }
  const ModelSpec& w = *spec.world;
  for (std::size_t e = 0; e < w.events.size(); ++e) {
    const std::string key = "event." + w.events[e].name + "_at_s";
    const bool ended = run->event == static_cast<int>(e);
    const double at = ended ? run->event_t : run->first_at[e];
    r.metrics["event." + w.events[e].name] = std::isfinite(at) ? 1.0 : 0.0;
    if (std::isfinite(at)) {
      r.metrics[key] = at;
      std::ostringstream os;
      os << w.events[e].label << " at t = " << at << (ended ? " s: the run ends there" : " s")
         << " (model.world.events." << w.events[e].name << ")";
      r.warnings.push_back(os.str());
    } else {
      r.undefined[key] = "the event did not occur in the run";
    }
  }
  for (std::size_t s = 0; s < w.channels.size(); ++s) {
    if (!w.channels[s].sensor.impulses) continue;
    const double n = static_cast<double>(run->sampled[s]);
    r.metrics["impulsive_fraction." + w.channels[s].name] =
        n > 0 ? static_cast<double>(run->impulsive[s]) / n : 0.0;
  }
  return run;
}

Status replay_events(const ModelSpec& spec, const ParamValues& values, const Dataset& d,
                     ModelResult& r) {
  if (!spec.world || spec.world->events.empty() || !d.has("t")) return Ok{};
  const ModelSpec& w = *spec.world;
  auto ev = ModelEval::create(w, values);
  if (!ev) return ev.err();
  std::vector<double> vars = (*ev)->vars();
  ExprGroup when;
  std::vector<double> value(w.events.size(), 0.0);
  for (std::size_t e = 0; e < w.events.size(); ++e)
    when.add(w.events[e].when.text, &value[e]);
  if (auto st = when.bind(w.symbols, vars.data()); !st) return st;
  // Each world state from its truth column in the log (NaN where it has none: no event fires).
  std::vector<const std::vector<double>*> truth(w.states.size(), nullptr);
  for (std::size_t i = 0; i < w.states.size(); ++i) {
    if (!w.truth[i].empty() && d.has(w.truth[i])) truth[i] = &d.col(w.truth[i]);
  }
  std::vector<double> at(w.events.size(), kNoSample);
  const auto& t = d.col("t");
  for (std::size_t k = 0; k < std::min(d.rows(), r.steps()); ++k) {
    vars[static_cast<std::size_t>(w.t_slot)] = t[k];
    for (std::size_t i = 0; i < truth.size(); ++i)
      vars[static_cast<std::size_t>(w.state_slots[i])] = truth[i] ? (*truth[i])[k] : kNoSample;
    when.eval();
    for (std::size_t e = 0; e < at.size(); ++e) {
      if (std::isnan(at[e]) && value[e] > 0.0) at[e] = t[k];
    }
  }
  for (std::size_t e = 0; e < w.events.size(); ++e) {
    const std::string key = "event." + w.events[e].name + "_at_s";
    r.metrics["event." + w.events[e].name] = std::isfinite(at[e]) ? 1.0 : 0.0;
    if (!std::isfinite(at[e])) {
      r.undefined[key] = "the event did not occur in the log's truth columns";
      continue;
    }
    r.metrics[key] = at[e];
    std::ostringstream os;
    os << w.events[e].label << " at t = " << at[e] << " s, in the log's truth (model.world.events."
       << w.events[e].name << ")";
    r.warnings.push_back(os.str());
  }
  return Ok{};
}

std::vector<MetricSpec> loop_metric_specs(const ModelSpec& spec) {
  std::vector<MetricSpec> out;
  if (!spec.controller) return out;
  for (const auto& e : spec.world->events) {
    out.push_back({"event." + e.name, e.label, "",
                   "1 when model.world.events." + e.name +
                       " occurred in the run (and ended it, unless it does not end runs), else 0: "
                       "its mean over seeds is the fraction",
                   MetricGroup::kScenario, Direction::kLower});
    out.push_back({"event." + e.name + "_at_s", e.label + " at", "s",
                   "the time of the first row where model.world.events." + e.name +
                       " holds (the run ends there unless the event does not end runs); undefined "
                       "when it did not occur",
                   MetricGroup::kScenario, Direction::kHigher});
  }
  for (const auto& c : spec.world->channels) {
    if (!c.sensor.impulses) continue;
    out.push_back({"impulsive_fraction." + c.name, "impulsive samples (" + c.name + ")", "",
                   "fraction of the world sensor's samples read during a burst of impulses",
                   MetricGroup::kScenario, Direction::kNone});
  }
  return out;
}

}  // namespace kfw::model
