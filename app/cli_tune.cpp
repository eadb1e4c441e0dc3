// kfw-cli tune, sweep and merge: the tuner over one or many logs, grid sweeps that can be split
// into shards, and the merge of shard parts (dispatched on each part's "kind").
#include <glob.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_commands.h"
#include "core/dataset.h"
#include "core/metrics.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/json_io.h"
#include "experiment/monte_carlo.h"
#include "experiment/tuning.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;
// Sweep documents keep their keys sorted (nlohmann::json), as they read back: a merged document
// is then byte for byte the one an unsharded sweep writes.
using Doc = nlohmann::json;

constexpr int kSweepPartVersion = 1;

bool has_glob(const std::string& s) {
  return s.find_first_of("*?[") != std::string::npos;
}

// Every --data in order; a pattern with * ? [ expands to its matches, sorted (exit 2: none).
Expected<std::vector<std::string>> expand_data(const std::vector<std::string>& given) {
  std::vector<std::string> out;
  for (const auto& g : given) {
    if (!has_glob(g)) {
      out.push_back(g);
      continue;
    }
    glob_t gl{};
    const int rc = ::glob(g.c_str(), 0, nullptr, &gl);
    std::vector<std::string> hits;
    for (std::size_t i = 0; rc == 0 && i < gl.gl_pathc; ++i)
      hits.emplace_back(gl.gl_pathv[i]);
    globfree(&gl);
    if (hits.empty()) return Error{"--data: no file matches " + quote_token(g)};
    std::sort(hits.begin(), hits.end());
    out.insert(out.end(), hits.begin(), hits.end());
  }
  return out;
}

// "KEY=V" for --lo / --hi.
Status parse_bound(const std::string& text, const char* option, std::string& key, double& v) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || !parse_double(text.substr(eq + 1), v)) {
    return Error{std::string(option) + " expects KEY=NUMBER, got " + quote_token(text)};
  }
  key = text.substr(0, eq);
  return Ok{};
}

Json metrics_json(const Metrics& m, const UndefinedMetrics& undefined) {
  return Json::parse(metrics_to_json(m, undefined));
}

// Warns when a truth-free tuning rests on innovations that are not white (coloured sensor
// errors make NLL/NIS pick a tuning that trusts that sensor far too much).
void warn_if_not_white(const Metrics& m, const TuneObjective& obj, std::ostream& err) {
  auto it = m.find("whiteness_p");
  if (obj.spec.key == "rmse" || it == m.end() || !std::isfinite(it->second)) return;
  if (it->second < 0.01) {
    err << "kfw-cli: warning: innovations are not white (Ljung-Box p = " << it->second
        << " < 0.01): a tuning by '" << obj.name << "' without truth is not trustworthy here\n";
  }
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v)
    s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

int cmd_tune(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto files = expand_data(a.data_all);
  if (!files) return fail(err, files.err());
  const std::optional<std::string> first =
      files->empty() ? std::nullopt : std::optional<std::string>(files->front());
  auto ws = open_any(a.target, first, a.sets);
  if (!ws) return fail(err, ws.err());
  if (auto st = apply_import_args(a.import, *ws); !st) return fail(err, st.err());
  // The selection: --params, else the preset's tunable keys.
  std::vector<SearchParam> params;
  if (a.params.empty()) {
    params = default_search(ws->preset);
    if (params.empty()) return fail(err, Error{"--params: this preset marks no key tunable"});
  }
  for (const auto& key : a.params) {
    auto p = search_param(ws->preset, key);
    if (!p) return fail(err, Error{"--params: " + p.error()});
    params.push_back(*p);
  }
  for (const auto* list : {&a.lo, &a.hi}) {
    const char* option = list == &a.lo ? "--lo" : "--hi";
    for (const auto& text : *list) {
      std::string key;
      double v = 0.0;
      if (auto st = parse_bound(text, option, key, v); !st) return fail(err, st.err());
      auto it = std::find_if(params.begin(), params.end(), [&](auto& p) { return p.key == key; });
      if (it == params.end()) {
        std::vector<std::string> keys;
        for (const auto& p : params)
          keys.push_back(p.key);
        return fail(err, Error{std::string(option) + ": " +
                               unknown_message("searched parameter", key, keys)});
      }
      if (auto st = ws->scenario->params().check(key, v); !st) {
        return fail(err, Error{std::string(option) + ": " + st.error()});
      }
      (list == &a.lo ? it->lo : it->hi) = v;
    }
  }
  for (const auto& p : params) {
    if (!(p.lo < p.hi) || (p.log && p.lo <= 0)) {
      return fail(err, Error{"--lo/--hi: " + p.key + ": need lo < hi" +
                             (p.log ? " and lo > 0 (a log-scale key)" : "")});
    }
  }
  auto method = parse_tune_method(a.method);
  if (!method) return fail(err, method.err());
  auto aggregate = parse_aggregate(a.aggregate);
  if (!aggregate) return fail(err, aggregate.err());
  if (a.budget < 1) return fail(err, Error{"--budget: must be at least 1 evaluation"});
  if (!(a.tol > 0) || !std::isfinite(a.tol)) return fail(err, Error{"--tol: must be > 0"});
  OutputSet outs = outputs_for(*ws);
  for (const auto& f : *files)
    outs.add_input(f);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  // The tuning set: every file, else one simulated dataset per seed, else the preset's dataset
  // (or a simulated one).
  std::vector<Dataset> data;
  std::vector<std::string> names;
  std::vector<ParamValues> fixed;  // per dataset: the seed it was simulated with
  if (a.seeds) {
    if (!files->empty()) {
      return fail(err, Error{"--seeds simulates each seed; it cannot be used with --data"});
    }
    auto seeds = seeds_for(a, *ws);
    if (!seeds) return fail(err, seeds.err());
    for (long long seed : *seeds) {
      ParamValues v = ws->values;
      v["sim.seed"] = static_cast<double>(seed);
      auto d = ws->scenario->simulate(v);
      if (!d) return fail(err, d.err());
      data.push_back(std::move(*d));
      names.push_back("seed " + std::to_string(seed));
      fixed.push_back({{"sim.seed", static_cast<double>(seed)}});
    }
  } else if (files->empty()) {
    auto d = load_dataset(*ws);
    if (!d) return fail(err, d.err());
    data.push_back(std::move(*d));
    names.push_back(ws->data_path ? *ws->data_path : "simulated");
  }
  for (const auto& f : *files) {
    auto d = load_dataset_file(*ws->scenario, f, ws->mapping);
    if (!d) return fail(err, d.err());
    data.push_back(std::move(*d));
    names.push_back(f);
  }
  // The objective must name a metric of this scenario and be defined on every dataset.
  std::vector<std::shared_ptr<const RunResult>> probes;
  fixed.resize(data.size());
  auto with_fixed = [&](ParamValues v, std::size_t i) {
    for (const auto& [k, x] : fixed[i])
      v[k] = x;
    return v;
  };
  for (std::size_t i = 0; i < data.size(); ++i) {
    auto probe = ws->scenario->run(data[i], with_fixed(ws->values, i));
    if (!probe) return fail(err, probe.err());
    probes.push_back(*probe);
  }
  const std::string name =
      a.objective.empty() ? default_objective(*probes.front(), params) : a.objective;
  auto objective = make_objective(*ws->scenario, name, probes.front().get());
  if (!objective) return fail(err, objective.err());
  double start_sum = 0.0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::string key = objective->spec.key;
    const bool undefined = !probes[i]->metrics.count(key) ||
                           (objective->with_nis && !probes[i]->metrics.count("nis_mean"));
    if (undefined) {
      std::string why = key == "rmse" ? " (no truth column?)" : "";
      if (auto u = probes[i]->undefined.find(key); u != probes[i]->undefined.end()) {
        why = " (" + u->second + ")";
      }
      return fail(err, Error{"--objective: " + quote_token(name) + " is not available on " +
                             names[i] + why});
    }
    start_sum += probes[i]->metrics.at(key);
  }
  std::vector<TuneLog> logs;
  for (std::size_t i = 0; i < data.size(); ++i)
    logs.push_back({names[i], &data[i], fixed[i]});
  TuneOptions opt;
  opt.method = *method;
  opt.aggregate = *aggregate;
  opt.budget = a.budget;
  opt.tol = a.tol;
  auto r = tune(*ws->scenario, logs, ws->values, params, *objective, opt);
  if (!r) return fail(err, r.err());

  Json j;
  j["objective"] = name;
  j["metric"] = objective->spec.key;
  j["direction"] = direction_name(objective->spec.direction);
  if (objective->spec.direction == Direction::kTarget) j["target"] = objective->spec.target;
  j["method"] = r->method;
  j["aggregate"] = aggregate_name(*aggregate);
  if (a.seeds) j["seeds"] = data.size();
  j["value"] = r->value;
  j["start_value"] = start_sum / static_cast<double>(data.size());
  j["evaluations"] = r->evaluations;
  for (const auto& p : params) {
    j["params"][p.key] = r->best.at(p.key);
    j["bounds"][p.key] = {p.lo, p.hi};
  }
  j["at_bound"] = r->at_bound;
  j["scale"] = Json::array();
  for (const auto& s : r->scales) {
    Json g = {{"group", s.group},
              {"keys", s.keys},
              {"determined_by_objective", s.determined},
              {"relative_change", s.change},
              {"relative_change_one_key", s.shape_change},
              {"set_by_consistency", s.by_consistency},
              {"nis_mean", s.nis_mean}};
    if (s.by_consistency) g["factor"] = s.factor;
    if (!s.note.empty()) g["note"] = s.note;
    j["scale"].push_back(g);
    if (!s.determined) {
      err << "kfw-cli: warning: '" << objective->spec.key << "' does not change when "
          << join(s.keys) << " scale together (relative change " << s.change
          << "): it sets their ratios only; the scale was set by consistency (NIS mean / dof = "
          << s.nis_mean << ")\n";
    }
    if (!s.note.empty()) err << "kfw-cli: warning: " << s.group << ": " << s.note << "\n";
  }
  if (!r->at_bound.empty()) {
    err << "kfw-cli: warning: the optimum sits on a search bound for " << join(r->at_bound)
        << " (widen it with --lo/--hi)\n";
  }
  j["logs"] = Json::array();
  for (const auto& l : r->logs) {
    Json e = {{"data", l.name}};
    if (std::isfinite(l.value)) e["value"] = l.value;
    e["metrics"] = metrics_json(l.metrics, {});
    j["logs"].push_back(e);
  }
  // The best run again, for its undefined metrics and their reasons.
  auto best = ws->scenario->run(data.front(), with_fixed(r->best, 0));
  j["metrics"] =
      best ? metrics_json((*best)->metrics, (*best)->undefined) : metrics_json(r->metrics, {});
  warn_if_not_white(r->metrics, *objective, err);
  if (a.out) {
    Preset p = ws->preset;
    p.values = r->best;
    if (!names.empty() && names.front() != "simulated" && !a.seeds) {
      p.data_path = std::filesystem::absolute(names.front()).string();
    }
    if (auto st = outs.stage(*a.out, preset_to_json(p)); !st) return fail(err, st.err());
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << j.dump(2) << "\n";
  return kExitOk;
}

namespace {

// A sweep as a JSON document: the grid, the metric and each point's value or why it stopped.
// Parts (one shard) and whole sweeps share it; no timings, no host names, so merging the parts
// of a sharded sweep gives the unsharded document byte for byte.
Doc sweep_document(const Workspace& ws, const std::vector<SweepAxis>& axes, const MetricSpec& spec,
                   const SweepResult& r, const Shard& shard, std::size_t total) {
  Doc j;
  j["kind"] = "sweep";
  j["version"] = kSweepPartVersion;
  j["scenario"] = ws.scenario->name();
  j["metric"] = spec.key;
  j["direction"] = direction_name(spec.direction);
  if (spec.direction == Direction::kTarget) j["target"] = spec.target;
  j["axes"] = Doc::array();
  for (const auto& ax : axes)
    j["axes"].push_back(
        {{"key", ax.key}, {"lo", ax.lo}, {"hi", ax.hi}, {"n", ax.n}, {"log", ax.log}});
  j["base"] = ws.values;
  j["shard"] = {{"index", shard.index}, {"count", shard.count}};
  j["total_points"] = total;
  j["points"] = Doc::array();
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    Doc p = {{"index", r.indices.empty() ? i : r.indices[i]}, {"at", r.points[i]}};
    if (!r.errors[i].empty()) {
      p["error"] = r.errors[i];
    } else if (auto it = r.metrics[i].find(spec.key); it != r.metrics[i].end()) {
      p["value"] = it->second;
    }
    j["points"].push_back(p);
  }
  return j;
}

// The summary printed by sweep and merge (best by the metric's direction, stopped runs), and
// the outputs: a .json document or a .csv table.
Status finish_sweep(const Doc& doc, const MetricSpec& spec, const CliArgs& a, OutputSet& outs,
                    std::ostream& out, std::ostream& err) {
  const Doc& points = doc.at("points");
  const Doc& axes = doc.at("axes");
  const std::string metric = doc.at("metric");
  std::size_t best = points.size(), defined = 0, stopped_n = 0;
  Json stopped = Json::array();
  std::string first_error;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Doc& p = points[i];
    if (p.contains("error")) {
      ++stopped_n;
      if (first_error.empty()) first_error = p.at("error");
      Json at;
      for (std::size_t k = 0; k < axes.size(); ++k)
        at[axes[k].at("key").get<std::string>()] = p.at("at").at(k).get<double>();
      stopped.push_back({{"at", at}, {"error", p.at("error").get<std::string>()}});
      continue;
    }
    if (!p.contains("value")) continue;
    ++defined;
    if (best == points.size() ||
        better(spec, p.at("value").get<double>(), points[best].at("value").get<double>())) {
      best = i;
    }
  }
  if (!points.empty() && stopped_n == points.size()) {
    return failure("sweep: every run stopped (first: " + first_error + ")");
  }
  if (best == points.size()) {
    return failure("sweep: " + quote_token(metric) + " has no value at any grid point");
  }
  if (!stopped.empty()) {
    err << "kfw-cli: warning: " << stopped.size() << " of " << points.size()
        << " runs stopped (listed under \"stopped\"; first: " << first_error << ")\n";
  }
  if (a.out) {
    const bool json = std::filesystem::path(*a.out).extension() == ".json";
    std::string text;
    if (json) {
      text = doc.dump(1) + "\n";
    } else {
      Dataset table;
      table.source = *a.out;
      for (const auto& ax : axes)
        table.add(ax.at("key").get<std::string>(), points.size());
      table.add(metric, points.size());
      for (std::size_t i = 0; i < points.size(); ++i) {
        for (std::size_t k = 0; k < axes.size(); ++k)
          table.columns[k][i] = points[i].at("at").at(k).get<double>();
        table.columns[axes.size()][i] =
            points[i].contains("value") ? points[i].at("value").get<double>() : std::nan("");
      }
      std::ostringstream csv;
      write_csv(csv, table);
      text = csv.str();
    }
    if (auto st = outs.stage(*a.out, text); !st) return st;
  }
  if (auto st = outs.commit(); !st) return st;
  Json j;
  j["metric"] = metric;
  j["direction"] = doc.at("direction").get<std::string>();
  if (doc.contains("target")) j["target"] = doc.at("target").get<double>();
  j["points"] = points.size();
  j["points_defined"] = defined;
  if (doc.contains("seeds")) j["seeds"] = doc.at("seeds").get<std::size_t>();
  j["best"] = points[best].at("value").get<double>();
  for (std::size_t k = 0; k < axes.size(); ++k)
    j["best_at"][axes[k].at("key").get<std::string>()] = points[best].at("at").at(k).get<double>();
  j["stopped"] = stopped;
  out << j.dump(2) << "\n";
  return Ok{};
}

}  // namespace

int cmd_sweep(const CliArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_workspace_for_cli(a);
  if (!ws) return fail(err, ws.err());
  std::optional<std::vector<long long>> seeds;
  if (a.seeds) {
    auto set = seeds_for(a, *ws);
    if (!set) return fail(err, set.err());
    seeds = std::move(*set);
    if (a.shard)
      return fail(err, Error{"--shard: not with --seeds on sweep (shard the grid alone)"});
  }
  std::vector<SweepAxis> axes;
  for (const auto& t : a.axes) {
    auto ax = parse_sweep_axis(ws->scenario->params(), t);
    if (!ax) return fail(err, ax.err());
    axes.push_back(*ax);
  }
  Shard shard;
  if (a.shard) {
    auto s = parse_shard(*a.shard, "--shard");
    if (!s) return fail(err, s.err());
    shard = *s;
    if (!a.out || std::filesystem::path(*a.out).extension() != ".json") {
      return fail(err, Error{"--shard: write the part with --out PART.json (kfw-cli merge reads "
                             "the parts)"});
    }
  }
  // Refused at once, before any run: the points of this shard (the whole grid without one).
  const std::size_t most = std::numeric_limits<std::size_t>::max();
  const std::size_t limit =
      a.max_points >= most / (shard.count + 1) ? most : (a.max_points + 1) * shard.count;
  const auto total = grid_size(axes, limit);
  if (!total || shard_size(*total, shard) > a.max_points) {
    return fail(
        err, Error{"--param: the grid has more than " + std::to_string(a.max_points) + " points" +
                   (a.shard ? " in this shard" : "") + "; raise --max-points to run it"});
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
  if (std::find(keys.begin(), keys.end(), metric) == keys.end()) {
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
                 : sweep(*ws->scenario, *d, ws->values, axes, 0, nullptr, shard);
  if (!r) return fail(err, r.err());
  Doc doc = sweep_document(*ws, axes, spec, *r, shard, *total);
  if (seeds) doc["seeds"] = seeds->size();
  if (auto st = finish_sweep(doc, spec, a, outs, out, err); !st) return fail(err, st.err());
  return kExitOk;
}

namespace {

// Merges the parts of a sharded sweep: the same grid, metric and base values, every shard once.
Status merge_sweep_impl(const std::vector<nlohmann::json>& parts, const CliArgs& a, OutputSet& outs,
                        std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& paths = a.parts;
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return st;
  }
  const Doc& first = parts.front();
  const auto count = first.at("shard").at("count").get<std::size_t>();
  std::vector<int> seen(count + 1, 0);
  std::map<std::size_t, Doc> points;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const Doc& p = parts[i];
    for (const char* key : {"version", "scenario", "metric", "axes", "base", "total_points"}) {
      if (p.at(key) != first.at(key)) {
        return Error{paths[i] + ": " + key + ": differs from " + paths.front() +
                     " (parts of different sweeps)"};
      }
    }
    if (p.at("shard").at("count") != first.at("shard").at("count")) {
      return Error{paths[i] + ": shard: split into a different number of shards"};
    }
    const auto index = p.at("shard").at("index").get<std::size_t>();
    if (index < 1 || index > count || seen[index]++) {
      return Error{paths[i] + ": shard " + std::to_string(index) + "/" + std::to_string(count) +
                   " given twice or out of range"};
    }
    for (const auto& pt : p.at("points"))
      points[pt.at("index").get<std::size_t>()] = pt;
  }
  for (std::size_t k = 1; k <= count; ++k) {
    if (!seen[k]) {
      return Error{"merge: shard " + std::to_string(k) + "/" + std::to_string(count) +
                   " is missing"};
    }
  }
  Doc doc = first;
  doc["shard"] = {{"index", 1}, {"count", 1}};
  doc["points"] = Doc::array();
  for (auto& [index, pt] : points)
    doc["points"].push_back(std::move(pt));
  if (doc.at("points").size() != first.at("total_points").get<std::size_t>()) {
    return Error{"merge: the parts hold " + std::to_string(doc.at("points").size()) + " of " +
                 first.at("total_points").dump() + " points"};
  }
  auto s = make_scenario(first.at("scenario").get<std::string>());
  MetricSpec spec;
  if (s) {
    spec = describe_metric(**s, first.at("metric").get<std::string>());
  } else {
    spec.key = first.at("metric");
  }
  // The direction and target the parts were judged by (a model's spec comes with the part).
  for (auto d : {Direction::kLower, Direction::kHigher, Direction::kTarget, Direction::kNone}) {
    if (first.at("direction") == direction_name(d)) spec.direction = d;
  }
  if (first.contains("target")) spec.target = first.at("target").get<double>();
  return finish_sweep(doc, spec, a, outs, out, err);
}

}  // namespace

Status merge_sweep_parts(const std::vector<nlohmann::json>& parts, const CliArgs& a,
                         OutputSet& outs, std::ostream& out, std::ostream& err) {
  try {
    return merge_sweep_impl(parts, a, outs, out, err);
  } catch (const nlohmann::json::exception& e) {
    // A part edited by hand: a key missing or of the wrong type.
    return Error{"merge: a part is malformed (" + std::string(e.what()) + ")"};
  }
}

}  // namespace kfw
