#include "cli.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/dataset.h"
#include "core/tuning.h"
#include "core/workspace.h"

namespace kfw {

namespace {

constexpr const char* kUsage =
    "usage: kfw-cli COMMAND ...\n"
    "  simulate SCENARIO|PRESET [--seed N] [--set key=value]... --out FILE.csv\n"
    "  run PRESET [--data FILE] [--set key=value]... [--out estimates.csv] [--metrics m.json]\n"
    "  gain PRESET [--data FILE] [--set key=value]...\n"
    "  tune PRESET [--data FILE] --params Q,R[,gamma...] --objective rmse|nll|nis [--out "
    "tuned.json]\n"
    "  sweep PRESET [--data FILE] --param key=lo:hi:n [--param ...] --metric NAME [--out "
    "sweep.csv]\n"
    "  params SCENARIO|PRESET      the parameter table (key, unit, range, default)\n"
    "  preset SCENARIO|PRESET [--set key=value]... --out FILE.json   write a full preset\n"
    "  list                        the scenarios and presets\n"
    "  CMD SCENARIO|PRESET [--data FILE] [--set key=value]...\n"
    "                              a scenario's own analysis (e.g. stats for underwater)\n"
    "  CMD FILE.csv [--set key=value]...\n"
    "                              the same, for the one scenario that offers CMD\n";

struct Args {
  std::vector<std::string> positional;
  std::vector<std::string> sets;
  std::optional<std::string> data, out, metrics, seed, params, objective, metric;
  std::vector<std::string> axes;  // sweep --param key=lo:hi:n
};

Expected<Args> parse(const std::vector<std::string>& a, std::size_t from) {
  Args r;
  for (std::size_t i = from; i < a.size(); ++i) {
    const std::string& s = a[i];
    auto value = [&](std::optional<std::string>& dst) -> Status {
      if (i + 1 >= a.size()) return Error{s + " needs a value"};
      dst = a[++i];
      return Ok{};
    };
    Status st = Ok{};
    if (s == "--set") {
      std::optional<std::string> v;
      st = value(v);
      if (st) r.sets.push_back(*v);
    } else if (s.rfind("--set=", 0) == 0) {
      r.sets.push_back(s.substr(6));
    } else if (s == "--data") {
      st = value(r.data);
    } else if (s == "--out") {
      st = value(r.out);
    } else if (s == "--metrics") {
      st = value(r.metrics);
    } else if (s == "--seed") {
      st = value(r.seed);
    } else if (s == "--params") {
      st = value(r.params);
    } else if (s == "--objective") {
      st = value(r.objective);
    } else if (s == "--metric") {
      st = value(r.metric);
    } else if (s == "--param") {
      std::optional<std::string> v;
      st = value(v);
      if (st) r.axes.push_back(*v);
    } else if (s.rfind("--", 0) == 0) {
      return Error{"unknown option " + s};
    } else {
      r.positional.push_back(s);
    }
    if (!st) return Error{st.error()};
  }
  return r;
}

nlohmann::json to_json(const Metrics& m) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : m) {
    if (std::isfinite(v)) {
      j[k] = v;
    } else {
      j[k] = nullptr;
    }
  }
  return j;
}

// A scenario name or a preset path both open a workspace.
Expected<Workspace> open_any(const std::string& name, const Args& a) {
  std::error_code ec;
  const bool looks_like_file =
      name.find('/') != std::string::npos || std::filesystem::path(name).extension() == ".json";
  if (!looks_like_file && !std::filesystem::is_regular_file(resolve_preset_path(name), ec)) {
    auto p = default_preset(name);
    if (!p) return Error{p.error()};
    Workspace ws;
    ws.preset = *p;
    auto s = make_scenario(name);
    ws.scenario = std::shared_ptr<const Scenario>(std::move(*s));
    ws.values = ws.preset.values;
    for (const auto& as : a.sets) {
      if (auto st = ws.scenario->params().apply_assignment(as, ws.values); !st) {
        return Error{st.error()};
      }
    }
    ws.data_path = a.data;
    return ws;
  }
  return open_workspace(name, a.data, a.sets);
}

int fail(std::ostream& err, const std::string& msg) {
  err << "kfw-cli: " << msg << "\n";
  return 2;
}

int cmd_simulate(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "simulate takes one scenario or preset");
  if (!a.out) return fail(err, "simulate needs --out FILE.csv");
  Args b = a;
  if (a.seed) b.sets.push_back("sim.seed=" + *a.seed);
  b.data.reset();
  auto ws = open_any(a.positional[0], b);
  if (!ws) return fail(err, ws.error());
  auto d = ws->scenario->simulate(ws->values);
  if (!d) return fail(err, d.error());
  if (auto st = write_csv_file(*a.out, *d); !st) return fail(err, st.error());
  out << "wrote " << *a.out << " (" << d->rows() << " rows, " << d->names.size() << " columns)\n";
  return 0;
}

int cmd_run(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "run takes one preset");
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.error());
  auto r = ws->scenario->run(*d, ws->values);
  if (!r) return fail(err, r.error());
  const RunResult& res = **r;
  for (const auto& w : res.warnings)
    err << "kfw-cli: warning: " << w << "\n";
  if (a.out) {
    if (auto st = write_csv_file(*a.out, res.table()); !st) return fail(err, st.error());
  }
  const std::string text = to_json(res.metrics).dump(2) + "\n";
  if (a.metrics) {
    if (auto st = write_text_file_atomic(*a.metrics, text); !st) return fail(err, st.error());
  }
  out << text;
  return 0;
}

int cmd_gain(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "gain takes one preset");
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  std::optional<Dataset> data;
  if (ws->data_path) {
    auto d = load_dataset(*ws);
    if (!d) return fail(err, d.error());
    data = std::move(*d);
  }
  auto g = ws->scenario->gain(ws->values, data ? &*data : nullptr);
  if (!g) return fail(err, g.error());
  out << to_json(*g).dump(2) << "\n";
  return 0;
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

int cmd_tune(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "tune takes one preset");
  if (!a.params) return fail(err, "tune needs --params key[,key...]");
  const std::string obj_name = a.objective.value_or("rmse");
  auto objective = objective_by_name(obj_name);
  if (!objective) return fail(err, objective.error());
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.error());
  std::vector<SearchParam> params;
  std::stringstream keys(*a.params);
  for (std::string key; std::getline(keys, key, ',');) {
    const ParamSpec* spec = ws->scenario->params().find(key);
    if (!spec) return fail(err, "--params: unknown parameter '" + key + "'");
    SearchParam p{key, spec->min, spec->max, spec->scale == Scale::kLog};
    if (auto r = ws->preset.ranges.find(key); r != ws->preset.ranges.end()) {
      p.lo = r->second.first;
      p.hi = r->second.second;
    }
    params.push_back(p);
  }
  // The objective must exist for this dataset (rmse needs truth).
  auto probe = ws->scenario->run(*d, ws->values);
  if (!probe) return fail(err, probe.error());
  if (!std::isfinite((*objective)((*probe)->metrics))) {
    return fail(err, "objective '" + obj_name + "' is not available on this dataset" +
                         (obj_name == "rmse" ? " (no truth column?)" : ""));
  }
  auto r = tune(*ws->scenario, *d, ws->values, params, *objective);
  if (!r) return fail(err, r.error());
  nlohmann::json j;
  j["objective"] = obj_name;
  j["value"] = r->objective;
  j["evaluations"] = r->evaluations;
  j["start_value"] = (*objective)((*probe)->metrics);
  for (const auto& p : params)
    j["params"][p.key] = r->best.at(p.key);
  j["metrics"] = to_json(r->metrics);
  warn_if_not_white(r->metrics, obj_name, err);
  if (a.out) {
    Preset p = ws->preset;
    p.values = r->best;
    if (ws->data_path) p.data_path = std::filesystem::absolute(*ws->data_path).string();
    if (auto st = save_preset(*a.out, p); !st) return fail(err, st.error());
  }
  out << j.dump(2) << "\n";
  return 0;
}

int cmd_sweep(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "sweep takes one preset");
  if (a.axes.empty()) return fail(err, "sweep needs --param key=lo:hi:n");
  if (!a.metric) return fail(err, "sweep needs --metric NAME");
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  std::vector<SweepAxis> axes;
  for (const auto& t : a.axes) {
    auto ax = parse_sweep_axis(ws->scenario->params(), t);
    if (!ax) return fail(err, ax.error());
    axes.push_back(*ax);
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.error());
  auto r = sweep(*ws->scenario, *d, ws->values, axes, 2);
  if (!r) return fail(err, r.error());
  std::size_t best = r->points.size();
  for (std::size_t i = 0; i < r->points.size(); ++i) {
    auto it = r->metrics[i].find(*a.metric);
    if (it == r->metrics[i].end() || !std::isfinite(it->second)) continue;
    if (best == r->points.size() || it->second < r->metrics[best].at(*a.metric)) best = i;
  }
  if (best == r->points.size()) return fail(err, "metric '" + *a.metric + "' is not available");
  if (a.out) {
    Dataset table;
    table.source = *a.out;
    for (std::size_t k = 0; k < axes.size(); ++k)
      table.add(axes[k].key, r->points.size());
    table.add(*a.metric, r->points.size());
    for (std::size_t i = 0; i < r->points.size(); ++i) {
      for (std::size_t k = 0; k < axes.size(); ++k)
        table.columns[k][i] = r->points[i][k];
      auto it = r->metrics[i].find(*a.metric);
      if (it != r->metrics[i].end()) table.columns[axes.size()][i] = it->second;
    }
    std::ostringstream os;
    write_csv(os, table);
    if (auto st = write_text_file_atomic(*a.out, os.str()); !st) return fail(err, st.error());
  }
  nlohmann::json j;
  j["metric"] = *a.metric;
  j["points"] = r->points.size();
  j["best"] = r->metrics[best].at(*a.metric);
  for (std::size_t k = 0; k < axes.size(); ++k)
    j["best_at"][axes[k].key] = r->points[best][k];
  out << j.dump(2) << "\n";
  return 0;
}

int cmd_preset(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "preset takes one scenario or preset");
  if (!a.out) return fail(err, "preset needs --out FILE.json");
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  Preset p = ws->preset;
  p.values = ws->values;
  if (auto st = save_preset(*a.out, p); !st) return fail(err, st.error());
  out << "wrote " << *a.out << "\n";
  return 0;
}

int cmd_params(const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) return fail(err, "params takes one scenario or preset");
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  const ParamTable& t = ws->scenario->params();
  for (const auto& s : t.specs()) {
    out << s.key << "\t" << t.format(s.key, ws->values.at(s.key)) << "\t[" << s.min << ", " << s.max
        << "]\t" << s.unit << "\t" << s.label << "\n";
  }
  return 0;
}

// A command a scenario offers (Scenario::commands()), e.g. `kfw-cli stats underwater --data f.csv`.
// `kfw-cli CMD FILE.csv` is short for `kfw-cli CMD SCENARIO --data FILE.csv` when exactly one
// scenario offers CMD.
int cmd_scenario(const std::string& cmd, Args a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) {
    return fail(err, "unknown command '" + cmd + "' (try --help)");
  }
  const std::string& first = a.positional[0];
  const bool csv = first.size() > 4 && (first.compare(first.size() - 4, 4, ".csv") == 0 ||
                                        first.compare(first.size() - 4, 4, ".CSV") == 0);
  if (csv && !a.data) {
    std::vector<std::string> offering;
    for (const auto& name : scenarios().names()) {
      const auto cmds = scenarios().make(name)->commands();
      if (std::find(cmds.begin(), cmds.end(), cmd) != cmds.end()) offering.push_back(name);
    }
    if (offering.size() != 1) {
      return fail(err, "unknown command '" + cmd + "' (try --help)");
    }
    a.data = first;
    a.positional[0] = offering.front();
  }
  auto ws = open_any(a.positional[0], a);
  if (!ws) return fail(err, ws.error());
  const auto cmds = ws->scenario->commands();
  if (std::find(cmds.begin(), cmds.end(), cmd) == cmds.end()) {
    return fail(err, "unknown command '" + cmd + "' for scenario '" + ws->scenario->name() +
                         "' (try --help)");
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.error());
  auto text = ws->scenario->command(cmd, *d, ws->values);
  if (!text) return fail(err, text.error());
  out << *text << "\n";
  return 0;
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
  out << "\n";
  return 0;
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    (args.empty() ? err : out) << kUsage;
    return args.empty() ? 2 : 0;
  }
  auto a = parse(args, 1);
  if (!a) return fail(err, a.error());
  const std::string& cmd = args[0];
  if (cmd == "simulate") return cmd_simulate(*a, out, err);
  if (cmd == "run") return cmd_run(*a, out, err);
  if (cmd == "gain") return cmd_gain(*a, out, err);
  if (cmd == "params") return cmd_params(*a, out, err);
  if (cmd == "preset") return cmd_preset(*a, out, err);
  if (cmd == "tune") return cmd_tune(*a, out, err);
  if (cmd == "sweep") return cmd_sweep(*a, out, err);
  if (cmd == "list") return cmd_list(out);
  return cmd_scenario(cmd, *a, out, err);
}

}  // namespace kfw
