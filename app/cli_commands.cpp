#include "cli_commands.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/dataset.h"
#include "core/gain_curve.h"
#include "core/metrics.h"
#include "core/monte_carlo.h"
#include "core/output.h"
#include "core/suggest.h"
#include "core/tuning.h"
#include "core/workspace.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Scenario names and preset names, for "did you mean".
std::vector<std::string> target_names() {
  std::vector<std::string> names = scenarios().names();
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(preset_dir(), ec)) {
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  }
  return names;
}

// The files a command on this workspace reads: an output may not be one of them.
OutputSet outputs_for(const Workspace& ws) {
  OutputSet o;
  o.add_input(ws.preset.path);
  if (ws.data_path) o.add_input(*ws.data_path);
  return o;
}

std::vector<std::string> param_keys(const ParamTable& t) {
  std::vector<std::string> keys;
  for (const auto& s : t.specs())
    keys.push_back(s.key);
  return keys;
}

// The metrics JSON of a result (flat, "undefined" block, never null) as a JSON value.
Json metrics_json(const Metrics& m, const UndefinedMetrics& undefined) {
  return Json::parse(metrics_to_json(m, undefined));
}

// Warns when a truth-free tuning rests on innovations that are not white (coloured sensor
// errors make NLL/NIS pick a tuning that trusts that sensor far too much).
void warn_if_not_white(const Metrics& m, const std::string& objective, std::ostream& err) {
  auto it = m.find("whiteness_p");
  if (objective == "rmse" || it == m.end() || !std::isfinite(it->second)) return;
  if (it->second < 0.01) {
    err << "kfw-cli: warning: innovations are not white (Ljung-Box p = " << it->second
        << " < 0.01): a tuning by '" << objective << "' without truth is not trustworthy here\n";
  }
}

void print_warnings(const RunResult& r, std::ostream& err) {
  for (const auto& w : r.warnings)
    err << "kfw-cli: warning: " << one_line(w) << "\n";
}

}  // namespace

// A scenario name or a preset (path or name in presets/) both open a workspace.
Expected<Workspace> open_any(const std::string& name, const std::optional<std::string>& data,
                             const std::vector<std::string>& sets) {
  std::error_code ec;
  const bool looks_like_file =
      name.find('/') != std::string::npos || std::filesystem::path(name).extension() == ".json";
  if (!looks_like_file && !std::filesystem::is_regular_file(resolve_preset_path(name), ec)) {
    auto p = default_preset(name);
    if (!p) {
      return Error{"no preset or scenario " + quote_token(name) +
                   did_you_mean(name, target_names())};
    }
    Workspace ws;
    ws.preset = *p;
    auto s = make_scenario(name);
    if (!s) return s.err();
    ws.scenario = std::shared_ptr<const Scenario>(std::move(*s));
    ws.values = ws.preset.values;
    for (const auto& as : sets) {
      if (auto st = ws.scenario->params().apply_assignment(as, ws.values); !st) return st.err();
    }
    ws.data_path = data;
    return ws;
  }
  return open_workspace(name, data, sets);
}

int fail(std::ostream& err, const Error& e) {
  err << "kfw-cli: " << one_line(e.message) << "\n";
  return e.exit_code;
}

int cmd_simulate(const CliArgs& a, std::ostream& out, std::ostream& err) {
  std::vector<std::string> sets = a.sets;
  if (a.seed) sets.push_back("sim.seed=" + std::to_string(*a.seed));
  auto ws = open_any(a.target, std::nullopt, sets);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  auto d = ws->scenario->simulate(ws->values);
  if (!d) return fail(err, d.err());
  std::ostringstream csv;
  write_csv(csv, *d);
  if (auto st = outs.stage(*a.out, csv.str()); !st) return fail(err, st.err());
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << "wrote " << *a.out << " (" << d->rows() << " rows, " << d->names.size() << " columns)\n";
  return kExitOk;
}

int cmd_run(const CliArgs& a, std::ostream& out, std::ostream& err) {
  if (a.seeds) return cmd_run_seeds(a, out, err);
  if (a.shard || a.out_dir || a.table) {
    const char* opt = a.shard ? "--shard" : a.out_dir ? "--out-dir" : "--table";
    return fail(err, Error{std::string(opt) + ": needs --seeds"});
  }
  auto ws = open_any(a.target, a.data, a.sets);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  if (a.metrics) {
    if (auto st = outs.add(*a.metrics, "--metrics"); !st) return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  auto r = ws->scenario->run(*d, ws->values);
  if (!r) return fail(err, r.err());
  const RunResult& res = **r;
  print_warnings(res, err);
  const std::string text = metrics_to_json(res.metrics, res.undefined) + "\n";
  if (a.out) {
    std::ostringstream csv;
    write_csv(csv, res.table());
    if (auto st = outs.stage(*a.out, csv.str()); !st) return fail(err, st.err());
  }
  if (a.metrics) {
    if (auto st = outs.stage(*a.metrics, text); !st) return fail(err, st.err());
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << text;
  return kExitOk;
}

namespace {

// gain --curve KEY: {"parameter", "log", "x": [...], "gains": {"K.x.z": [...]}, "at": {...}}.
int print_gain_curve(const Scenario& s, const ParamValues& values, const std::string& key,
                     std::size_t points, const Dataset* data, std::ostream& out,
                     std::ostream& err) {
  const auto keys = gain_curve_parameters(s);
  if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
    return fail(err,
                Error{"--curve: " + unknown_message("continuous filter parameter", key, keys)});
  }
  auto c = gain_curve(s, values, key, points, data);
  if (!c) return fail(err, c.err());
  nlohmann::ordered_json j;
  j["parameter"] = key;
  j["log"] = c->log;
  j["x"] = c->x;
  nlohmann::ordered_json gains = nlohmann::ordered_json::object(), at = gains;
  for (std::size_t e = 0; e < c->entries.size(); ++e) {
    nlohmann::ordered_json v = nlohmann::ordered_json::array();
    for (double y : c->values[e])
      v.push_back(std::isfinite(y) ? nlohmann::ordered_json(y) : nlohmann::ordered_json());
    gains[c->entries[e]] = v;
    at[c->entries[e]] = c->at[e];
  }
  j["gains"] = gains;
  j["at"] = {{"value", c->at_x}, {"gains", at}};
  out << j.dump(2) << "\n";
  return kExitOk;
}

}  // namespace

int cmd_gain(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, a.data, a.sets);
  if (!ws) return fail(err, ws.err());
  std::optional<Dataset> data;
  if (ws->data_path) {
    auto d = load_dataset(*ws);
    if (!d) return fail(err, d.err());
    data = std::move(*d);
  }
  if (a.curve)
    return print_gain_curve(*ws->scenario, ws->values, *a.curve, a.curve_points,
                            data ? &*data : nullptr, out, err);
  auto g = ws->scenario->gain(ws->values, data ? &*data : nullptr);
  if (!g) return fail(err, g.err());
  out << metrics_to_json(*g, {}) << "\n";
  return kExitOk;
}

int cmd_tune(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, a.data, a.sets);
  if (!ws) return fail(err, ws.err());
  const ParamTable& table = ws->scenario->params();
  std::vector<SearchParam> params;
  for (const auto& key : a.params) {
    const ParamSpec* spec = table.find(key);
    if (!spec) {
      return fail(err, Error{"--params: " + unknown_message("parameter", key, param_keys(table))});
    }
    SearchParam p{key, spec->min, spec->max, spec->scale == Scale::kLog};
    if (auto r = ws->preset.ranges.find(key); r != ws->preset.ranges.end()) {
      p.lo = r->second.first;
      p.hi = r->second.second;
    }
    params.push_back(p);
  }
  OutputSet outs = outputs_for(*ws);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  // The objective must name a metric of this scenario and exist on this dataset (rmse: truth).
  auto probe = ws->scenario->run(*d, ws->values);
  if (!probe) return fail(err, probe.err());
  const std::string& name = a.objective;
  std::vector<std::string> names = {"rmse", "nll", "nis"};
  const auto keys = metric_keys(*ws->scenario, probe->get());
  names.insert(names.end(), keys.begin(), keys.end());
  if (!contains(names, name)) {
    return fail(err, Error{"--objective: " + unknown_message("objective", name, names)});
  }
  auto objective = objective_by_name(name);
  if (!objective) return fail(err, objective.err());
  const double start_value = (*objective)((*probe)->metrics);
  if (!std::isfinite(start_value)) {
    std::string why = name == "rmse" ? " (no truth column?)" : "";
    const std::string metric = name == "nis" ? "nis_mean" : name;
    if (auto u = (*probe)->undefined.find(metric); u != (*probe)->undefined.end()) {
      why = " (" + u->second + ")";
    }
    return fail(err, Error{"--objective: " + quote_token(name) +
                           " is not available on this dataset" + why});
  }
  auto r = tune(*ws->scenario, *d, ws->values, params, *objective);
  if (!r) return fail(err, r.err());
  Json j;
  j["objective"] = name;
  j["value"] = r->objective;
  j["evaluations"] = r->evaluations;
  j["start_value"] = start_value;
  for (const auto& p : params)
    j["params"][p.key] = r->best.at(p.key);
  // The best run again, for its undefined metrics and their reasons.
  auto best = ws->scenario->run(*d, r->best);
  j["metrics"] =
      best ? metrics_json((*best)->metrics, (*best)->undefined) : metrics_json(r->metrics, {});
  warn_if_not_white(r->metrics, name, err);
  if (a.out) {
    Preset p = ws->preset;
    p.values = r->best;
    if (ws->data_path) p.data_path = std::filesystem::absolute(*ws->data_path).string();
    if (auto st = outs.stage(*a.out, preset_to_json(p)); !st) return fail(err, st.err());
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << j.dump(2) << "\n";
  return kExitOk;
}

int cmd_sweep(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, a.data, a.sets);
  if (!ws) return fail(err, ws.err());
  std::optional<std::vector<long long>> seeds;
  if (a.seeds) {
    auto set = seeds_for(a, *ws);
    if (!set) return fail(err, set.err());
    seeds = std::move(*set);
  }
  std::vector<SweepAxis> axes;
  for (const auto& t : a.axes) {
    auto ax = parse_sweep_axis(ws->scenario->params(), t);
    if (!ax) return fail(err, ax.err());
    axes.push_back(*ax);
  }
  // Refused at once, before any run: the product of the axes' sizes, without overflow.
  std::size_t points = 1;
  for (const auto& ax : axes) {
    const auto n = static_cast<std::size_t>(ax.n);
    if (points > a.max_points / std::max<std::size_t>(n, 1)) {
      return fail(err, Error{"--param: the grid has more than " + std::to_string(a.max_points) +
                             " points; raise --max-points to run it"});
    }
    points *= n;
  }
  OutputSet outs = outputs_for(*ws);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  // One run at the base values tells which metrics this scenario and dataset produce.
  // (A base run that stops numerically is no reason not to sweep: grid points may run.)
  auto probe = ws->scenario->run(*d, ws->values);
  if (!probe && probe.exit_code() != kExitFailed) return fail(err, probe.err());
  const RunResult* base = probe ? probe->get() : nullptr;
  const std::string& metric = a.metric;
  const auto keys = metric_keys(*ws->scenario, base);
  if (!contains(keys, metric)) {
    return fail(err, Error{"--metric: " + unknown_message("metric", metric, keys)});
  }
  if (base) {
    if (auto u = base->undefined.find(metric); u != base->undefined.end()) {
      return fail(err, Error{"--metric: " + quote_token(metric) +
                             " is undefined on this dataset (" + u->second + ")"});
    }
  }
  const MetricSpec spec = describe_metric(*ws->scenario, metric, base);
  // With --seeds each point is scored by the metric's mean over the seeds.
  auto r = seeds ? sweep_over_seeds(*ws->scenario, ws->values, axes, *seeds)
                 : sweep(*ws->scenario, *d, ws->values, axes, 2);
  if (!r) return fail(err, r.err());
  const std::size_t none = r->points.size();
  std::size_t best = none;
  auto value_at = [&](std::size_t i) {
    auto it = r->metrics[i].find(metric);
    return it == r->metrics[i].end() ? std::nan("") : it->second;
  };
  std::size_t defined = 0;
  for (std::size_t i = 0; i < r->points.size(); ++i) {
    const double v = value_at(i);
    if (!std::isfinite(v)) continue;
    ++defined;
    if (best == none || better(spec, v, value_at(best))) best = i;
  }
  // Runs that stopped are listed with their point; the sweep fails only when none ran.
  Json stopped = Json::array();
  std::string first_error;
  for (std::size_t i = 0; i < r->points.size(); ++i) {
    if (r->errors[i].empty()) continue;
    if (first_error.empty()) first_error = r->errors[i];
    Json at;
    for (std::size_t k = 0; k < axes.size(); ++k)
      at[axes[k].key] = r->points[i][k];
    stopped.push_back({{"at", at}, {"error", r->errors[i]}});
  }
  if (r->stopped() == r->points.size()) {
    return fail(err, failure("sweep: every run stopped (first: " + first_error + ")"));
  }
  if (best == none) {
    return fail(err, failure("sweep: " + quote_token(metric) + " has no value at any grid point"));
  }
  if (!stopped.empty()) {
    err << "kfw-cli: warning: " << stopped.size() << " of " << r->points.size()
        << " runs stopped (listed under \"stopped\"; first: " << first_error << ")\n";
  }
  if (a.out) {
    Dataset table;
    table.source = *a.out;
    for (const auto& ax : axes)
      table.add(ax.key, r->points.size());
    table.add(metric, r->points.size());
    for (std::size_t i = 0; i < r->points.size(); ++i) {
      for (std::size_t k = 0; k < axes.size(); ++k)
        table.columns[k][i] = r->points[i][k];
      table.columns[axes.size()][i] = value_at(i);  // NaN: an empty cell
    }
    std::ostringstream csv;
    write_csv(csv, table);
    if (auto st = outs.stage(*a.out, csv.str()); !st) return fail(err, st.err());
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  Json j;
  j["metric"] = metric;
  j["direction"] = direction_name(spec.direction);
  if (spec.direction == Direction::kTarget) j["target"] = spec.target;
  j["points"] = r->points.size();
  j["points_defined"] = defined;
  if (seeds) j["seeds"] = seeds->size();
  j["best"] = value_at(best);
  for (std::size_t k = 0; k < axes.size(); ++k)
    j["best_at"][axes[k].key] = r->points[best][k];
  j["stopped"] = stopped;
  out << j.dump(2) << "\n";
  return kExitOk;
}

int cmd_preset(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, std::nullopt, a.sets);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  Preset p = ws->preset;
  p.values = ws->values;
  if (auto st = outs.stage(*a.out, preset_to_json(p)); !st) return fail(err, st.err());
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << "wrote " << *a.out << "\n";
  return kExitOk;
}

int cmd_params(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, std::nullopt, a.sets);
  if (!ws) return fail(err, ws.err());
  const ParamTable& t = ws->scenario->params();
  for (const auto& s : t.specs()) {
    out << s.key << "\t" << t.format(s.key, ws->values.at(s.key)) << "\t[" << s.min << ", " << s.max
        << "]\t" << s.unit << "\t" << s.label << "\n";
  }
  return kExitOk;
}

// The metric declarations (engine/core/metrics.h and the scenario's own), as the README shows them.
int cmd_metrics(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target, std::nullopt, {});
  if (!ws) return fail(err, ws.err());
  std::vector<MetricSpec> specs = shared_metric_specs();
  for (const auto& s : ws->scenario->metric_specs())
    specs.push_back(s);
  auto sense = [](const MetricSpec& s) {
    std::ostringstream os;
    if (s.direction == Direction::kTarget) {
      os << "target " << s.target;
    } else {
      os << direction_name(s.direction);
    }
    if (s.good_lo || s.good_hi) {
      os << "; good " << (s.good_lo ? *s.good_lo : -INFINITY) << "…"
         << (s.good_hi ? *s.good_hi : INFINITY);
    }
    return os.str();
  };
  if (a.markdown)
    out << "| key | label | unit | group | better | description |\n|---|---|---|---|---|---|\n";
  for (const auto& s : specs) {
    if (a.markdown) {
      out << "| `" << s.key << "` | " << s.label << " | " << s.unit << " | " << group_name(s.group)
          << " | " << sense(s) << " | " << s.description << " |\n";
    } else {
      out << s.key << "\t" << s.label << "\t" << s.unit << "\t" << group_name(s.group) << "\t"
          << sense(s) << "\t" << s.description << "\n";
    }
  }
  return kExitOk;
}

// `kfw-cli CMD FILE.csv` is short for `kfw-cli CMD SCENARIO --data FILE.csv` when exactly one
// scenario offers CMD.
int cmd_scenario(const std::string& cmd, CliArgs a, std::ostream& out, std::ostream& err) {
  const std::string& first = a.target;
  const bool csv = first.size() > 4 && (first.compare(first.size() - 4, 4, ".csv") == 0 ||
                                        first.compare(first.size() - 4, 4, ".CSV") == 0);
  std::vector<std::string> offering;
  for (const auto& name : scenarios().names()) {
    const auto cmds = scenarios().make(name)->commands();
    if (std::find(cmds.begin(), cmds.end(), cmd) != cmds.end()) offering.push_back(name);
  }
  if (csv && !a.data) {
    if (offering.size() != 1) {
      return fail(err, Error{cmd + " FILE.csv: more than one scenario offers '" + cmd +
                             "'; name one (kfw-cli " + cmd + " SCENARIO --data FILE.csv)"});
    }
    a.data = first;
    a.target = offering.front();
  }
  auto ws = open_any(a.target, a.data, a.sets);
  if (!ws) return fail(err, ws.err());
  const auto cmds = ws->scenario->commands();
  if (std::find(cmds.begin(), cmds.end(), cmd) == cmds.end()) {
    std::string who;
    for (const auto& n : offering)
      who += (who.empty() ? "" : ", ") + n;
    return fail(err, Error{"scenario '" + ws->scenario->name() + "' has no command '" + cmd +
                           "' (offered by: " + who + ")"});
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  auto text = ws->scenario->command(cmd, *d, ws->values);
  if (!text) return fail(err, text.err());
  out << *text << "\n";
  return kExitOk;
}

int cmd_list(std::ostream& out) {
  out << "scenarios:";
  for (const auto& n : scenarios().names())
    out << " " << n;
  out << "\npresets (" << preset_dir() << "):";
  std::error_code ec;
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(preset_dir(), ec)) {
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  for (const auto& n : names)
    out << " " << n;
  names.clear();
  for (const auto& e : std::filesystem::directory_iterator(preset_dir() + "/models", ec)) {
    if (e.path().extension() == ".json") names.push_back("models/" + e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  out << "\nmodels (" << preset_dir() << "/models):";
  for (const auto& n : names)
    out << " " << n;
  out << "\n";
  return kExitOk;
}

}  // namespace kfw
