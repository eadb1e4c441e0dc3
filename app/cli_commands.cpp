#include "cli_commands.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "codegen/c_export.h"
#include "core/dataset.h"
#include "core/metrics.h"
#include "core/retired.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/output.h"
#include "document/preset.h"
#include "document/session.h"
#include "document/workspace.h"
#include "experiment/gain_curve.h"
#include "experiment/monte_carlo.h"
#include "filter/noise_estimate.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;

void print_warnings(const RunResult& r, std::ostream& err) {
  for (const auto& w : r.warnings)
    err << "kfw-cli: warning: " << one_line(w) << "\n";
}

}  // namespace

// The files a command on this workspace reads: an output may not be one of them.
OutputSet outputs_for(const Workspace& ws) {
  OutputSet o;
  o.add_input(ws.preset.path);
  if (ws.data_path) o.add_input(*ws.data_path);
  if (ws.mapping_path) o.add_input(*ws.mapping_path);
  return o;
}

// A preset (path, or name in presets/; a retired built-in's name is its model file's) opens a
// workspace; the preset's notices (a retired scenario loaded as its model file) go to `err`.
Expected<Workspace> open_any(const std::string& name, const std::optional<std::string>& data,
                             const std::vector<std::string>& sets, std::ostream& err) {
  std::error_code ec;
  const bool looks_like_file =
      name.find('/') != std::string::npos || std::filesystem::path(name).extension() == ".json";
  if (!looks_like_file && !find_retired(name) &&
      !std::filesystem::is_regular_file(resolve_preset_path(name), ec)) {
    return Error{"no preset " + quote_token(name) + preset_name_hint(name)};
  }
  auto ws = open_workspace(name, data, sets);
  if (ws) print_notices(ws->preset.notices, err);
  return ws;
}

Expected<Workspace> open_workspace_for_cli(const TargetArgs& target, const DataArgs& data,
                                           std::ostream& err) {
  auto ws = open_any(target.preset, data.file, target.sets, err);
  if (!ws) return ws;
  if (auto st = apply_import_args(data.import, *ws); !st) return st.err();
  return ws;
}

std::string preset_content_hash(const Workspace& ws) {
  if (!ws.preset.path.empty()) {
    if (auto h = file_hash(ws.preset.path)) return *h;
  }
  return text_hash(preset_to_json(ws.preset));
}

void print_notices(const std::vector<std::string>& notices, std::ostream& err) {
  for (const auto& n : notices)
    err << "kfw-cli: notice: " << one_line(n) << "\n";
}

int fail(std::ostream& err, const Error& e) {
  err << "kfw-cli: " << one_line(e.message) << "\n";
  return e.exit_code;
}

int cmd_simulate(const SimulateArgs& a, std::ostream& out, std::ostream& err) {
  std::vector<std::string> sets = a.target.sets;
  if (a.seed) sets.push_back("sim.seed=" + std::to_string(*a.seed));
  auto ws = open_any(a.target.preset, std::nullopt, sets, err);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  if (auto st = outs.add(a.out, "--out"); !st) return fail(err, st.err());
  auto d = ws->scenario->simulate(ws->values);
  if (!d) return fail(err, d.err());
  const auto columns = table_columns(*d);
  auto write = [&](OutputStream& os) { return write_csv_stream(os, columns, d->rows()); };
  if (auto st = outs.stage_stream(a.out, write); !st) return fail(err, st.err());
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << "wrote " << a.out << " (" << d->rows() << " rows, " << d->names.size() << " columns)\n";
  return kExitOk;
}

int cmd_run(const RunArgs& a, std::ostream& out, std::ostream& err) {
  const RunSeedsArgs& mc = a.seeds;
  if (mc.seeds) return cmd_run_seeds(a, out, err);
  if (mc.shard || mc.out_dir || mc.table) {
    const char* opt = mc.shard ? "--shard" : mc.out_dir ? "--out-dir" : "--table";
    return fail(err, Error{std::string(opt) + ": needs --seeds"});
  }
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  const OutputArgs& o = a.output;
  if (o.out) {
    if (auto st = outs.add(*o.out, "--out"); !st) return fail(err, st.err());
  }
  if (o.metrics) {
    if (auto st = outs.add(*o.metrics, "--metrics"); !st) return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  auto r = ws->scenario->run(*d, ws->values);
  if (!r) return fail(err, r.err());
  const RunResult& res = **r;
  print_warnings(res, err);
  const std::string text = metrics_to_json(res.metrics, res.undefined) + "\n";
  const std::vector<TableColumn> columns = o.out ? res.table_view() : std::vector<TableColumn>{};
  if (o.out) {
    auto write = [&](OutputStream& os) { return write_csv_stream(os, columns, res.steps()); };
    if (auto st = outs.stage_stream(*o.out, write); !st) return fail(err, st.err());
  }
  if (o.metrics) {
    if (auto st = outs.stage(*o.metrics, text); !st) return fail(err, st.err());
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << text;
  return kExitOk;
}

namespace {

// gain --curve KEY [--x NAME]: {"parameter", "log", "x": [...], ["x_quantity", "x_values"],
// "gains": {"K.x.z": [...]}, "at": {...}}.
int print_gain_curve(const Scenario& s, const ParamValues& values, const std::string& key,
                     const std::string& x_key, std::size_t points, const Dataset* data,
                     std::ostream& out, std::ostream& err) {
  const auto keys = gain_curve_parameters(s);
  if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
    return fail(err,
                Error{"--curve: " + unknown_message("continuous filter parameter", key, keys)});
  }
  auto c = gain_curve(s, values, key, points, data, "K.", x_key);
  if (!c) return fail(err, c.err());
  nlohmann::ordered_json j;
  j["parameter"] = key;
  j["log"] = c->log;
  j["x"] = c->x;
  if (!c->x_key.empty()) {
    // The same points against the derived quantity (null where the steady state fails).
    nlohmann::ordered_json v = nlohmann::ordered_json::array();
    for (double y : c->x_metric)
      v.push_back(std::isfinite(y) ? nlohmann::ordered_json(y) : nlohmann::ordered_json());
    j["x_quantity"] = c->x_key;
    j["x_values"] = v;
  }
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

int cmd_gain(const GainArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  std::optional<Dataset> data;
  if (ws->data_path) {
    auto d = load_dataset(*ws);
    if (!d) return fail(err, d.err());
    data = std::move(*d);
  }
  if (a.x && !a.curve) return fail(err, Error{"--x needs --curve KEY (the parameter swept)"});
  if (a.curve)
    return print_gain_curve(*ws->scenario, ws->values, *a.curve, a.x.value_or(""), a.points,
                            data ? &*data : nullptr, out, err);
  auto g = ws->scenario->gain(ws->values, data ? &*data : nullptr);
  if (!g) return fail(err, g.err());
  out << metrics_to_json(*g, {}) << "\n";
  return kExitOk;
}

int cmd_preset(const PresetArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target.preset, std::nullopt, a.target.sets, err);
  if (!ws) return fail(err, ws.err());
  OutputSet outs = outputs_for(*ws);
  if (auto st = outs.add(a.out, "--out"); !st) return fail(err, st.err());
  Preset p = ws->preset;
  p.values = ws->values;
  p.path = a.out;  // the data path is written relative to where the file goes
  if (auto st = outs.stage(a.out, preset_to_json(p)); !st) return fail(err, st.err());
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << "wrote " << a.out << "\n";
  return kExitOk;
}

int cmd_export_c(const ExportCArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  codegen::CExportOptions o = codegen::default_options(ws->preset.path);
  if (a.prefix) o.prefix = *a.prefix;
  o.single = a.single;
  o.steady = a.steady;
  o.runtime_params = a.params_struct;
  if (codegen::exports_steady(*ws->scenario, ws->values, a.steady)) {
    std::optional<Dataset> data;
    if (ws->data_path && !a.dt) {
      auto d = load_dataset(*ws);
      if (!d) return fail(err, d.err());
      data = std::move(*d);
    }
    auto dt = codegen::steady_interval(*ws->scenario, ws->values, a.dt, data ? &*data : nullptr);
    if (!dt) return fail(err, dt.err());
    o.steady_dt = *dt;
  } else if (a.dt) {
    return fail(err, Error{"--dt: only with --steady (the full filter takes each row's interval)"});
  }
  auto files = codegen::export_c(*ws->scenario, ws->values, o);
  if (!files) return fail(err, files.err());
  std::vector<std::string> inputs{ws->preset.path};
  if (ws->data_path) inputs.push_back(*ws->data_path);
  if (auto st = codegen::write_c_export(a.out_dir, o.prefix, *files, inputs); !st)
    return fail(err, st.err());
  const std::filesystem::path dir(a.out_dir);
  out << "wrote " << (dir / (o.prefix + ".h")).string() << ", "
      << (dir / (o.prefix + ".c")).string() << ", " << (dir / (o.prefix + "_example.c")).string()
      << "\n";
  return kExitOk;
}

int cmd_params(const ParamsArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.target.preset, std::nullopt, a.target.sets, err);
  if (!ws) return fail(err, ws.err());
  const ParamTable& t = ws->scenario->params();
  for (const auto& s : t.specs()) {
    out << s.key << "\t" << t.format(s.key, ws->values.at(s.key)) << "\t[" << s.min << ", " << s.max
        << "]\t" << s.unit << "\t" << s.label << "\n";
  }
  return kExitOk;
}

// The metric declarations (engine/core/metrics.h and the scenario's own), as the README shows them.
int cmd_metrics(const MetricsArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_any(a.preset, std::nullopt, {}, err);
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

int cmd_noise(const NoiseArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  if (auto st = check_noise_links(*ws->scenario, ws->preset.path); !st) {
    return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  auto e = estimate_noise(*ws->scenario, *d, ws->values);
  if (!e) return fail(err, e.err());
  out << noise_to_json(*e) << "\n";
  return kExitOk;
}

// The shipped presets (preset_dir(), not models/) that offer `cmd`.
static std::vector<std::string> offering_presets(const std::string& cmd) {
  const auto offers = [&](const Scenario& s) {
    const auto cmds = s.commands();
    return std::find(cmds.begin(), cmds.end(), cmd) != cmds.end();
  };
  std::vector<std::string> out;
  std::vector<std::string> presets;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(preset_dir(), ec)) {
    if (e.path().extension() == ".json") presets.push_back(e.path().stem().string());
  }
  std::sort(presets.begin(), presets.end());
  for (const auto& name : presets) {
    auto p = load_preset(preset_dir() + "/" + name + ".json");
    if (p && p->scenario == "model" && p->instance && offers(*p->instance)) out.push_back(name);
  }
  return out;
}

// `kfw-cli CMD FILE.csv` is short for `kfw-cli CMD SCENARIO --data FILE.csv` when exactly one
// scenario offers CMD.
int cmd_scenario(const std::string& cmd, ScenarioCommandArgs a, std::ostream& out,
                 std::ostream& err) {
  const std::string first = a.target.preset;
  const bool csv = first.size() > 4 && (first.compare(first.size() - 4, 4, ".csv") == 0 ||
                                        first.compare(first.size() - 4, 4, ".CSV") == 0);
  if (csv && !a.data.file) {
    // Loads every shipped preset: only for the shorthand and the "offered by" of a refusal.
    const std::vector<std::string> offering = offering_presets(cmd);
    if (offering.size() != 1) {
      return fail(err, Error{cmd + " FILE.csv: " + std::to_string(offering.size()) +
                             " shipped presets offer '" + cmd + "'; name one (kfw-cli " + cmd +
                             " PRESET --data FILE.csv)"});
    }
    a.data.file = first;
    a.target.preset = offering.front();
  }
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  const auto cmds = ws->scenario->commands();
  if (std::find(cmds.begin(), cmds.end(), cmd) == cmds.end()) {
    std::string who;
    for (const auto& n : offering_presets(cmd))
      who += (who.empty() ? "" : ", ") + n;
    // A model file by the name it was given (every model scenario is called "model").
    const std::string who_lacks =
        ws->scenario->name() == "model" ? a.target.preset : ws->scenario->name();
    return fail(
        err, Error{"'" + who_lacks + "' has no command '" + cmd + "' (offered by: " + who + ")"});
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  auto text = ws->scenario->command(cmd, *d, ws->values);
  if (!text) return fail(err, text.err());
  out << *text << "\n";
  return kExitOk;
}

int cmd_list(std::ostream& out) {
  out << "presets (" << preset_dir() << "):";
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
