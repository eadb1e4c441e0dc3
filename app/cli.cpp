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
#include "core/workspace.h"

namespace kfw {

namespace {

constexpr const char* kUsage =
    "usage: kfw-cli COMMAND ...\n"
    "  simulate SCENARIO|PRESET [--seed N] [--set key=value]... --out FILE.csv\n"
    "  run PRESET [--data FILE] [--set key=value]... [--out estimates.csv] [--metrics m.json]\n"
    "  gain PRESET [--data FILE] [--set key=value]...\n"
    "  params SCENARIO|PRESET      the parameter table (key, unit, range, default)\n"
    "  preset SCENARIO|PRESET [--set key=value]... --out FILE.json   write a full preset\n"
    "  list                        the scenarios and presets\n"
    "  CMD SCENARIO|PRESET [--data FILE] [--set key=value]...\n"
    "                              a scenario's own analysis (e.g. stats for underwater)\n";

struct Args {
  std::vector<std::string> positional;
  std::vector<std::string> sets;
  std::optional<std::string> data, out, metrics, seed;
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
int cmd_scenario(const std::string& cmd, const Args& a, std::ostream& out, std::ostream& err) {
  if (a.positional.size() != 1) {
    return fail(err, "unknown command '" + cmd + "' (try --help)");
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
  if (cmd == "list") return cmd_list(out);
  return cmd_scenario(cmd, *a, out, err);
}

}  // namespace kfw
