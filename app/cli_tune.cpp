// kfw-cli tune: the tuner over one log or a tuning set (many logs, or the datasets of simulator
// seeds). Sweeps are in cli_sweep.cpp.
#include <glob.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_commands.h"
#include "cli_job.h"
#include "core/dataset.h"
#include "core/metrics.h"
#include "core/suggest.h"
#include "data/json_io.h"
#include "experiment/tune_part.h"
#include "experiment/tuning.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;

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
  if (!obj.truth_free() || it == m.end() || !std::isfinite(it->second)) return;
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

// The selection (--params, else the preset's tunable keys) with its bounds (--lo, --hi, else the
// preset's range).
Expected<std::vector<SearchParam>> search_params(const TuneArgs& a, const Workspace& ws) {
  std::vector<SearchParam> params;
  if (a.params.empty()) {
    params = default_search(ws.preset);
    if (params.empty()) return Error{"--params: " + no_tunable_message(ws.preset)};
  }
  for (const auto& key : a.params) {
    auto p = search_param(ws.preset, key);
    if (!p) return Error{"--params: " + p.error()};
    params.push_back(*p);
  }
  for (const auto* list : {&a.lo, &a.hi}) {
    const char* option = list == &a.lo ? "--lo" : "--hi";
    for (const auto& text : *list) {
      std::string key;
      double v = 0.0;
      if (auto st = parse_bound(text, option, key, v); !st) return st.err();
      auto it = std::find_if(params.begin(), params.end(), [&](auto& p) { return p.key == key; });
      if (it == params.end()) {
        std::vector<std::string> keys;
        for (const auto& p : params)
          keys.push_back(p.key);
        return Error{std::string(option) + ": " + unknown_message("searched parameter", key, keys)};
      }
      if (auto st = ws.scenario->params().check(key, v); !st) {
        return Error{std::string(option) + ": " + st.error()};
      }
      (list == &a.lo ? it->lo : it->hi) = v;
    }
  }
  for (const auto& p : params) {
    if (!(p.lo < p.hi) || (p.log && p.lo <= 0)) {
      return Error{"--lo/--hi: " + p.key + ": need lo < hi" +
                   (p.log ? " and lo > 0 (a log-scale key)" : "")};
    }
  }
  return params;
}

// --method, --aggregate, --budget and --tol.
Expected<TuneOptions> tune_options(const TuneArgs& a) {
  auto method = parse_tune_method(a.method);
  if (!method) return method.err();
  auto aggregate = parse_aggregate(a.aggregate);
  if (!aggregate) return aggregate.err();
  if (a.budget < 1) return Error{"--budget: must be at least 1 evaluation"};
  if (!(a.tol > 0) || !std::isfinite(a.tol)) return Error{"--tol: must be > 0"};
  TuneOptions opt;
  opt.method = *method;
  opt.aggregate = *aggregate;
  opt.budget = a.budget;
  opt.tol = a.tol;
  opt.threads = a.jobs;
  return opt;
}

// The datasets tuned over, each with its name and the values it is always run with.
struct TuningSet {
  std::vector<Dataset> data;
  std::vector<std::string> names;
  std::vector<ParamValues> fixed;  // per dataset: the seed it was simulated with
  ParamValues with_fixed(ParamValues v, std::size_t i) const {
    for (const auto& [k, x] : fixed[i])
      v[k] = x;
    return v;
  }
};

// The tuning set: every file, else one simulated dataset per seed, else the preset's dataset
// (or a simulated one).
Expected<TuningSet> tuning_set(const TuneArgs& a, const std::vector<std::string>& files,
                               const Workspace& ws) {
  TuningSet set;
  if (a.seeds) {
    if (!files.empty()) return Error{"--seeds simulates each seed; it cannot be used with --data"};
    auto seeds = seeds_for(*a.seeds, std::nullopt, ws);
    if (!seeds) return seeds.err();
    for (long long seed : *seeds) {
      ParamValues v = ws.values;
      v["sim.seed"] = static_cast<double>(seed);
      auto d = ws.scenario->simulate(v);
      if (!d) return d.err();
      set.data.push_back(std::move(*d));
      set.names.push_back("seed " + std::to_string(seed));
      set.fixed.push_back({{"sim.seed", static_cast<double>(seed)}});
    }
  } else if (files.empty()) {
    auto d = load_dataset(ws);
    if (!d) return d.err();
    set.data.push_back(std::move(*d));
    set.names.push_back(ws.data_path ? *ws.data_path : "simulated");
  }
  for (const auto& f : files) {
    auto d = load_dataset_file(*ws.scenario, f, ws.mapping);
    if (!d) return d.err();
    set.data.push_back(std::move(*d));
    set.names.push_back(f);
  }
  set.fixed.resize(set.data.size());
  return set;
}

// The objective, by name, and its value at the start averaged over the set.
struct StartedObjective {
  std::string name;  // as given (--objective), or the default
  std::string from;  // "--objective", or the default's reason
  TuneObjective objective;
  double start_value = 0.0;
};

// The objective must name a metric of this scenario and be defined on every dataset.
Expected<StartedObjective> start_objective(const TuneArgs& a, const Workspace& ws,
                                           const TuningSet& set,
                                           const std::vector<SearchParam>& params) {
  std::vector<std::shared_ptr<const RunResult>> probes;
  for (std::size_t i = 0; i < set.data.size(); ++i) {
    auto probe = ws.scenario->run(set.data[i], set.with_fixed(ws.values, i));
    if (!probe) return probe.err();
    probes.push_back(*probe);
  }
  DefaultObjective chosen{a.objective, "--objective"};
  if (a.objective.empty()) chosen = default_objective(ws.preset, *probes.front(), params);
  const std::string& name = chosen.name;
  auto objective = make_objective(*ws.scenario, name, probes.front().get());
  if (!objective) {
    if (a.objective.empty()) return Error{"default_objective: " + objective.error()};
    return objective.err();
  }
  double start_sum = 0.0;
  for (std::size_t i = 0; i < set.data.size(); ++i) {
    const std::string key = objective->spec.key;
    const bool undefined = !probes[i]->metrics.count(key) ||
                           (objective->combined() && !probes[i]->metrics.count("nis_mean"));
    if (undefined) {
      std::string why = key == "rmse" ? " (no truth column?)" : "";
      if (auto u = probes[i]->undefined.find(key); u != probes[i]->undefined.end()) {
        why = " (" + u->second + ")";
      }
      return Error{"--objective: " + quote_token(name) + " is not available on " + set.names[i] +
                   why};
    }
    start_sum += probes[i]->metrics.at(key);
  }
  return StartedObjective{name, chosen.why, *objective,
                          start_sum / static_cast<double>(set.data.size())};
}

// The scale groups' reports, with a warning for each the objective could not set.
Json scale_reports(const TuneResult& r, const TuneObjective& objective, std::ostream& err) {
  Json scales = Json::array();
  for (const auto& s : r.scales) {
    Json g = {{"group", s.group},
              {"keys", s.keys},
              {"determined_by_objective", s.determined},
              {"relative_change", s.change},
              {"relative_change_one_key", s.shape_change},
              {"set_by_consistency", s.by_consistency},
              {"nis_mean", s.nis_mean}};
    if (s.by_consistency) g["factor"] = s.factor;
    if (!s.note.empty()) g["note"] = s.note;
    scales.push_back(g);
    if (!s.determined) {
      err << "kfw-cli: warning: '" << objective.spec.key << "' does not change when "
          << join(s.keys) << " scale together (relative change " << s.change
          << "): it sets their ratios only; the scale was set by consistency (NIS mean / dof = "
          << s.nis_mean << ")\n";
    }
    if (!s.note.empty()) err << "kfw-cli: warning: " << s.group << ": " << s.note << "\n";
  }
  return scales;
}

// What tune prints: the objective, the tuned values and bounds, the scale groups, each log's
// metrics and the best run's; warnings go to `err`.
Json tune_report(const TuneArgs& a, const Workspace& ws, const TuningSet& set,
                 const std::vector<SearchParam>& params, const TuneOptions& opt,
                 const StartedObjective& o, const TuneResult& r, std::ostream& err) {
  Json j;
  j["objective"] = o.name;
  j["objective_from"] = o.from;
  if (a.objective.empty()) {
    err << "kfw-cli: objective " << quote_token(o.name) << " (" << o.from
        << "; --objective chooses another)\n";
  }
  j["metric"] = o.objective.spec.key;
  j["direction"] = direction_name(o.objective.spec.direction);
  if (o.objective.spec.direction == Direction::kTarget) j["target"] = o.objective.spec.target;
  j["method"] = r.method;
  j["aggregate"] = aggregate_name(opt.aggregate);
  if (a.seeds) j["seeds"] = set.data.size();
  j["value"] = r.value;
  j["start_value"] = o.start_value;
  if (o.objective.combined()) j["objective_value"] = r.objective;  // the metric and its NIS term
  j["evaluations"] = r.evaluations;
  for (const auto& p : params) {
    j["params"][p.key] = r.best.at(p.key);
    j["bounds"][p.key] = {p.lo, p.hi};
  }
  j["at_bound"] = r.at_bound;
  if (r.trade_off) {
    const TradeOff& t = *r.trade_off;
    j["trade_off"] = {{"metric", t.metric},     {"start_value", t.start_value},
                      {"value", t.best_value},  {"start_nis_mean", t.start_nis},
                      {"nis_mean", t.best_nis}, {"cost", t.cost()},
                      {"costly", t.costly()}};
    if (t.costly()) err << "kfw-cli: warning: " << t.message() << "\n";
  }
  j["scale"] = scale_reports(r, o.objective, err);
  if (!r.at_bound.empty()) {
    err << "kfw-cli: warning: the optimum sits on a search bound for " << join(r.at_bound)
        << " (widen it with --lo/--hi)\n";
  }
  j["logs"] = Json::array();
  for (const auto& l : r.logs) {
    Json e = {{"data", l.name}};
    if (std::isfinite(l.value)) e["value"] = l.value;
    e["metrics"] = metrics_json(l.metrics, {});
    j["logs"].push_back(e);
  }
  // The best run again, for its undefined metrics and their reasons.
  auto best = ws.scenario->run(set.data.front(), set.with_fixed(r.best, 0));
  j["metrics"] =
      best ? metrics_json((*best)->metrics, (*best)->undefined) : metrics_json(r.metrics, {});
  warn_if_not_white(r.metrics, o.objective, err);
  return j;
}

}  // namespace

int cmd_tune(const TuneArgs& a, std::ostream& out, std::ostream& err) {
  auto files = expand_data(a.data);
  if (!files) return fail(err, files.err());
  const std::optional<std::string> first =
      files->empty() ? std::nullopt : std::optional<std::string>(files->front());
  auto ws = open_any(a.target.preset, first, a.target.sets, err);
  if (!ws) return fail(err, ws.err());
  if (auto st = apply_import_args(a.import, *ws); !st) return fail(err, st.err());
  auto params = search_params(a, *ws);
  if (!params) return fail(err, params.err());
  auto opt = tune_options(a);
  if (!opt) return fail(err, opt.err());
  std::optional<Shard> shard;
  if (a.shard) {
    auto s = parse_shard(*a.shard, "--shard");
    if (!s) return fail(err, s.err());
    if (!a.out)
      return fail(err, Error{"--shard: needs --out PART.json (kfw-cli merge joins them)"});
    shard = *s;
  }
  const ParamValues preset_values = ws->values;
  if (shard) start_tune_shard(*shard, *params, ws->values);
  OutputSet outs = outputs_for(*ws);
  for (const auto& f : *files)
    outs.add_input(f);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  auto set = tuning_set(a, *files, *ws);
  if (!set) return fail(err, set.err());
  auto objective = start_objective(a, *ws, *set, *params);
  if (!objective) return fail(err, objective.err());
  std::vector<TuneLog> logs;
  for (std::size_t i = 0; i < set->data.size(); ++i)
    logs.push_back({set->names[i], &set->data[i], set->fixed[i]});
  CliJob job(err, a.progress, "evaluations");
  opt->cancel = job.cancel();
  const auto budget = static_cast<std::size_t>(opt->budget);
  opt->progress = [&job, budget](int evaluations, double best) {
    job.progress(static_cast<std::size_t>(evaluations), budget, "best " + std::to_string(best));
  };
  auto r = tune(*ws->scenario, logs, ws->values, *params, objective->objective, *opt);
  job.finish();
  if (const int code = job.interrupted()) return fail(err, Error{job.interrupted_message(), code});
  if (!r) return fail(err, r.err());
  const Json j = tune_report(a, *ws, *set, *params, *opt, *objective, *r, err);
  if (a.out) {
    Preset p = ws->preset;
    p.values = r->best;
    if (!set->names.empty() && set->names.front() != "simulated" && !a.seeds) {
      p.data_path = std::filesystem::absolute(set->names.front()).string();
    }
    p.path = *a.out;  // the data path is written relative to where the file goes
    if (shard) {
      TunePart part{ws->scenario->name(),
                    a.target.preset,
                    preset_content_hash(*ws),
                    preset_values,
                    *shard,
                    {},
                    objective->name,
                    r->objective,
                    r->best,
                    preset_to_json(p),
                    j};
      for (const auto& sp : *params)
        part.start[sp.key] = ws->values.at(sp.key);
      if (auto st = stage_json(outs, *a.out, tune_part_to_json(part), 1); !st) {
        return fail(err, st.err());
      }
    } else if (auto st = outs.stage(*a.out, preset_to_json(p)); !st) {
      return fail(err, st.err());
    }
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << j.dump(2) << "\n";
  return kExitOk;
}

}  // namespace kfw
