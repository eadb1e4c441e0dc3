// kfw-cli's one command-line declaration (CLI11): every command with its typed options, its help
// and its errors; the command bodies are in cli_commands.cpp.
#include "cli.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <map>
#include <memory>

#include "cli_commands.h"
#include "core/scenario.h"
#include "core/suggest.h"
#include "document/import_args_cli.h"
#include "experiment/grammar.h"
#include "model/model_stats.h"

#ifndef KFW_VERSION
#error "KFW_VERSION comes from CMake's project(VERSION)"
#endif

namespace kfw {

namespace {

constexpr const char* kPresetHelp = "a preset file or a preset name in presets/ (kfw-cli list)";

constexpr const char* kExitCodes =
    "Exit codes: 0 the command did its work; 2 the command, an argument, a preset, a data file\n"
    "or an output path is invalid (checked before any work, so nothing is written); 1 the work\n"
    "failed (a write error, a run that breaks down numerically). Errors are one line.\n"
    "KFW_NATIVE=1: model expressions compiled by the system's C compiler, cached in\n"
    "$XDG_CACHE_HOME/kfw (docs/speed.md \"Native path\"); without a compiler, a notice.\n";

// Commands offered by scenarios (Scenario::commands()): name -> who offers it (a model file's
// commands, model/model_stats.h, as "model files that declare it").
std::map<std::string, std::vector<std::string>> scenario_commands() {
  std::map<std::string, std::vector<std::string>> cmds;
  for (const auto& c : model::model_commands())
    cmds[c].push_back("model files that declare it");
  return cmds;
}

// The declaration and what it parses into: one option struct per command (cli_options.h).
struct Cli {
  CLI::App app{"kfw-cli: the Kalman filter tuning workbench, headless.", "kfw-cli"};
  SimulateArgs simulate;
  RunArgs run;
  MergeArgs merge;
  GainArgs gain;
  TuneArgs tune;
  SweepArgs sweep;
  ParamsArgs params;
  PresetArgs preset;
  ExportCArgs export_c;
  MetricsArgs metrics;
  InspectArgs inspect;
  NoiseArgs noise;
  UpgradeArgs upgrade;
  std::map<std::string, ScenarioCommandArgs> scenario;  // by command name
  std::string topic;                                    // help TOPIC
};

// Options shared by several commands: one place for their names, types and help.
void add_preset(CLI::App* c, std::string& preset, const std::string& help = kPresetHelp) {
  c->add_option("PRESET", preset, help)->type_name("")->required();
}

void add_sets(CLI::App* c, std::vector<std::string>& sets) {
  c->add_option("--set", sets, "set a parameter (repeatable); kfw-cli params PRESET lists the keys")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false)
      ->take_all();
}

// The preset, --data with the import options, and --set, in this order.
void add_target_and_data(CLI::App* c, TargetArgs& t, DataArgs& d,
                         const std::string& help = kPresetHelp) {
  add_preset(c, t.preset, help);
  c->add_option_function<std::string>(
       "--data", [&d](const std::string& v) { d.file = v; },
       "the dataset (CSV); default: the preset's, else simulated")
      ->type_name("FILE.csv");
  add_import_options(c, d.import);
  add_sets(c, t.sets);
}

// An optional path (or other text) option.
CLI::Option* add_path(CLI::App* c, const std::string& name, std::optional<std::string>& dst,
                      const std::string& type, const std::string& help) {
  return c
      ->add_option_function<std::string>(
          name, [&dst](const std::string& v) { dst = v; }, help)
      ->type_name(type);
}

// A required path option.
void add_required_path(CLI::App* c, const std::string& name, std::string& dst,
                       const std::string& type, const std::string& help) {
  c->add_option_function<std::string>(
       name, [&dst](const std::string& v) { dst = v; }, help)
      ->type_name(type)
      ->required();
}

void declare_simulate(CLI::App& app, SimulateArgs& a) {
  CLI::App* c = app.add_subcommand("simulate", "simulate a dataset from the sim.* parameters");
  add_preset(c, a.target.preset);
  c->add_option_function<long long>(
       "--seed", [&a](const long long& v) { a.seed = v; }, "the simulator's seed (sim.seed)")
      ->type_name("N");
  add_sets(c, a.target.sets);
  add_required_path(c, "--out", a.out, "FILE.csv", "where to write the dataset");
}

constexpr const char* kProgressHelp =
    "progress on stderr even when it is not a terminal (a line every 10 %, for CI logs); "
    "SIGINT/SIGTERM stop the job: nothing written, exit 130/143";

// --jobs N: how many threads a parallel command uses (results do not depend on it).
void add_jobs(CLI::App* c, int& jobs) {
  c->add_option("--jobs", jobs,
                "worker threads (default: every core this process may use, as taskset or a "
                "Slurm allocation leaves it); the output is the same for every N")
      ->type_name("N")
      ->check(CLI::Range(1, 4096));
}

void declare_run(CLI::App& app, RunArgs& a) {
  CLI::App* c =
      app.add_subcommand("run", "run the filter over a dataset and print its metrics (JSON)");
  add_target_and_data(c, a.target, a.data);
  add_path(c, "--out", a.output.out, "FILE.csv",
           "write the per-step estimates (--seeds: the part, JSON)");
  add_path(c, "--metrics", a.output.metrics, "FILE.json",
           "write the metrics too (--seeds: with ANEES/ANIS at every step)");
  add_path(c, "--seeds", a.seeds.seeds, "SET",
           "Monte Carlo: simulate and filter each seed (1..50, 3,7,9); mean, sd, min, max");
  add_path(c, "--shard", a.seeds.shard, "i/N", "with --seeds: run seeds i, i+N, ... into --out");
  add_path(c, "--out-dir", a.seeds.out_dir, "DIR", "with --seeds: one estimates file per seed");
  c->add_flag("--table", a.seeds.table, "with --seeds: a readable table instead of JSON");
  c->add_flag("--progress", a.seeds.progress, kProgressHelp);
  add_jobs(c, a.seeds.jobs);
}

void declare_merge(CLI::App& app, MergeArgs& a) {
  CLI::App* c = app.add_subcommand(
      "merge",
      "merge the parts of a sharded run (run --seeds --shard, sweep --shard, tune --shard)");
  c->add_option("PART", a.parts, "the part files (JSON, one per shard)")->type_name("PART.json");
  add_path(c, "--resume", a.resume, "DIR",
           "instead: list DIR's missing or invalid part_<i>.json and print the array indices to "
           "resubmit (\"3,7-9\"; empty when complete)");
  add_path(c, "--metrics", a.output.metrics, "FILE.json", "write the merged result (JSON) too");
  add_path(c, "--out", a.output.out, "FILE.json|FILE.csv",
           "write the merged sweep (sweep parts), the merged part (Monte Carlo) or the best "
           "start's tuned preset (tune parts)");
  c->add_flag("--table", a.table, "a readable table instead of JSON");
}

void declare_gain(CLI::App& app, GainArgs& a) {
  CLI::App* c = app.add_subcommand("gain", "print the steady-state gains (closed form and DARE)");
  add_target_and_data(c, a.target, a.data);
  add_path(c, "--curve", a.curve, "KEY",
           "the gain curve: the steady-state gains over KEY's declared range (JSON)");
  c->add_option("--points", a.points, "points of the gain curve")
      ->type_name("N")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  add_path(c, "--x", a.x, "NAME",
           "with --curve: also give the curve against this steady-state quantity (a derived "
           "scalar such as beta, or another entry gain prints)");
}

// tune: the selection, the objective and the optimiser's settings.
void add_tune_search(CLI::App* c, TuneArgs& a) {
  c->add_option("--params", a.params,
                "the parameters to search; default: the preset's tunable (a model file that "
                "marks none: the parameters of its Q and R)")
      ->type_name("KEY[,KEY...]")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->take_all();
  c->add_option("--objective", a.objective,
                "a metric key (minimised, maximised or driven to its target by its direction), "
                "rmse+nis (RMSE with the noise scale set by NIS consistency) or rmse+anis (RMSE "
                "+ |ln NIS mean/dof|); default: the preset's default_objective, else rmse+nis "
                "with truth and a scale group, rmse+anis with truth, else nll")
      ->type_name("NAME");
  c->add_option("--method", a.method,
                "bobyqa (local, default), sbplx (local), direct (DIRECT-L, global) or crs "
                "(CRS2, global); global ones end with a local polish")
      ->type_name("NAME")
      ->capture_default_str();
  c->add_option("--lo", a.lo, "a search bound (repeatable); default: the preset's range")
      ->type_name("KEY=V")
      ->allow_extra_args(false);
  c->add_option("--hi", a.hi, "a search bound (repeatable); default: the preset's range")
      ->type_name("KEY=V")
      ->allow_extra_args(false);
  c->add_option("--budget", a.budget, "the most evaluations (each runs every dataset)")
      ->type_name("N")
      ->capture_default_str();
  c->add_option("--tol", a.tol,
                "stop when a step improves the objective by less than this fraction")
      ->type_name("X")
      ->capture_default_str();
  c->add_option("--aggregate", a.aggregate,
                "over several datasets: mean, or worst by the metric's direction")
      ->type_name("mean|worst")
      ->capture_default_str();
}

void declare_tune(CLI::App& app, TuneArgs& a) {
  CLI::App* c = app.add_subcommand("tune", "search the parameters that best meet an objective");
  add_preset(c, a.target.preset);
  c->add_option("--data", a.data,
                "a dataset (CSV); repeat it or give a glob for a tuning set; default: the "
                "preset's, else simulated")
      ->type_name("FILE.csv")
      ->allow_extra_args(false)
      ->take_all();
  add_import_options(c, a.import);  // the same mapping for every log of the tuning set
  add_sets(c, a.target.sets);
  add_tune_search(c, a);
  add_path(c, "--seeds", a.seeds, "SET",
           "tune over the datasets of these simulator seeds (a tuning set, like --data)");
  add_path(c, "--out", a.out, "FILE.json", "write the tuned preset (--shard: the part)");
  c->add_flag("--progress", a.progress, kProgressHelp);
  add_jobs(c, a.jobs);
  add_path(c, "--shard", a.shard, "i/N",
           "one of N independent starts (1: the preset's values, i > 1: a Halton point of the "
           "search box) into --out PART.json; kfw-cli merge keeps the best");
}

void declare_sweep(CLI::App& app, SweepArgs& a) {
  CLI::App* c =
      app.add_subcommand("sweep", "run every point of a grid and report the best by a metric");
  add_target_and_data(c, a.target, a.data);
  c->add_option("--param", a.axes,
                "a grid axis (repeatable; grid points in row-major order, the first axis "
                "slowest)")
      ->type_name("KEY=lo:hi:n[:log]")
      ->allow_extra_args(false)
      ->take_all()
      ->required();
  c->add_option("--metric", a.metric, "the metric to compare; best by its direction")
      ->type_name("NAME")
      ->required();
  add_path(c, "--out", a.out, "FILE.csv|FILE.json",
           "write every grid point and its metric (.json: a document kfw-cli merge reads)");
  add_path(c, "--seeds", a.seeds, "SET",
           "score each point by the metric's mean over these simulator seeds");
  c->add_option("--max-points", a.max_points,
                "refuse a grid (or a shard) larger than this (default 1000000): a typo in n is "
                "caught before hours of work")
      ->type_name("N")
      ->check(CLI::PositiveNumber);
  c->footer(
      "A grid is lo:hi:n, with :log or :lin for the spacing (kfw-cli help grammar);\n"
      "without either, log-scale parameters are spaced in log10.");
  add_path(c, "--shard", a.shard, "i/N",
           "run only shard i of N (grid points k with k mod N = i-1)");
  c->add_flag("--progress", a.progress, kProgressHelp);
  add_jobs(c, a.jobs);
}

void declare_params(CLI::App& app, ParamsArgs& a) {
  CLI::App* c =
      app.add_subcommand("params", "print the parameter table: key, value, range, unit, label");
  add_preset(c, a.target.preset);
  add_sets(c, a.target.sets);
}

void declare_preset(CLI::App& app, PresetArgs& a) {
  CLI::App* c =
      app.add_subcommand("preset", "write a full preset (every parameter) with --set applied");
  add_preset(c, a.target.preset);
  add_sets(c, a.target.sets);
  add_required_path(c, "--out", a.out, "FILE.json", "where to write the preset");
}

void declare_export_c(CLI::App& app, ExportCArgs& a) {
  CLI::App* c = app.add_subcommand(
      "export-c", "write the filter as dependency-free C99: NAME.h, NAME.c, NAME_example.c");
  add_target_and_data(c, a.target, a.data);
  c->add_option("--out-dir", a.out_dir, "the directory the three files go to")
      ->type_name("DIR")
      ->capture_default_str();
  add_path(c, "--prefix", a.prefix, "NAME",
           "the files' and functions' prefix (a C identifier); default: the preset's file name");
  c->add_flag("--float", a.single, "single precision throughout (no double-precision FPU)");
  c->add_flag("--steady", a.steady,
              "the fixed-gain filter with the DARE gain (linear time-invariant models)");
  c->add_flag("--params-struct", a.params_struct,
              "the parameters the filter reads in a struct set at NAME_init (one compiled filter, "
              "other values; NAME_example takes KEY=VALUE) instead of constants");
  c->add_option("--dt", a.dt,
                "--steady: the fixed interval (s); default: the data's median interval, else "
                "the simulation step")
      ->type_name("S");
}

void declare_metrics(CLI::App& app, MetricsArgs& a) {
  CLI::App* c = app.add_subcommand(
      "metrics", "list the metrics a scenario reports: key, label, unit, group, direction");
  add_preset(c, a.preset);
  c->add_flag("--markdown", a.markdown, "print a Markdown table (the README's tables)");
}

void declare_inspect(CLI::App& app, InspectArgs& a) {
  CLI::App* c = app.add_subcommand("inspect",
                                   "read a CSV: separator, columns, rows, time span and rate, and "
                                   "the mapping kfw would guess for a preset");
  c->add_option("FILE", a.file, "the CSV file")->type_name("")->required();
  c->add_option_function<std::string>(
       "PRESET", [&a](const std::string& v) { a.preset = v; },
       "guess the roles of this preset or scenario")
      ->type_name("");
  add_import_options(c, a.import);
  c->add_flag("--json", a.json, "print JSON");
}

void declare_noise(CLI::App& app, NoiseArgs& a) {
  CLI::App* c = app.add_subcommand(
      "noise",
      "the white-noise level of every column linked to a parameter, from the high-frequency "
      "PSD (seed 000, eq. 3), and the parameter values it proposes (JSON)");
  add_target_and_data(c, a.target, a.data);
  c->footer(
      "A model file links a column with \"noise_param\" on a channel or an input\n"
      "(presets/models/README.md, \"Noise links\").");
}

void declare_upgrade(CLI::App& app, UpgradeArgs& a) {
  CLI::App* c = app.add_subcommand(
      "upgrade",
      "rewrite an old preset or session (retired scenarios included) in the current form");
  c->add_option("FILE", a.file, "the preset or session (JSON)")->type_name("")->required();
  c->add_flag("--check", a.check,
              "write nothing: exit 0 when current, 1 when an upgrade would change it (printed)");
  add_path(c, "--out", a.out, "FILE.json", "write the upgraded file here (FILE is left as it is)");
  c->footer(
      "Without --out, FILE is rewritten atomically and the original is kept as FILE.bak\n"
      "(refused when FILE.bak exists).");
}

const CLI::App* find_command(const CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == name) return sub;
  }
  return nullptr;
}

// The commands scenarios offer, each with its own option struct in `cli.scenario`.
void declare_scenario_commands(CLI::App& app, Cli& cli) {
  for (const auto& [name, offering] : scenario_commands()) {
    if (find_command(app, name)) continue;  // a built-in command wins
    std::string who;
    for (const auto& s : offering)
      who += (who.empty() ? "" : ", ") + s;
    CLI::App* c = app.add_subcommand(name, "a scenario's own analysis, offered by: " + who);
    ScenarioCommandArgs& a = cli.scenario[name];
    add_target_and_data(c, a.target, a.data,
                        std::string(kPresetHelp) + "; or FILE.csv, short for PRESET --data " +
                            "FILE.csv when one shipped preset offers " + name);
  }
}

void declare(Cli& cli) {
  CLI::App& app = cli.app;
  app.get_formatter()->column_width(30);
  app.set_help_flag("-h,--help", "print this help and exit");
  app.allow_extras();  // unknown names are answered with "did you mean" (see check_extras)

  declare_simulate(app, cli.simulate);
  declare_run(app, cli.run);
  declare_merge(app, cli.merge);
  declare_gain(app, cli.gain);
  declare_tune(app, cli.tune);
  declare_sweep(app, cli.sweep);
  declare_params(app, cli.params);
  declare_preset(app, cli.preset);
  declare_export_c(app, cli.export_c);
  declare_metrics(app, cli.metrics);
  app.add_subcommand("list", "list the scenarios and presets");
  declare_inspect(app, cli.inspect);
  declare_noise(app, cli.noise);
  declare_upgrade(app, cli.upgrade);
  declare_scenario_commands(app, cli);

  CLI::App* c = app.add_subcommand("help", "print the help of a command, or of a topic: grammar");
  c->add_option("TOPIC", cli.topic, "a command or 'grammar'");

  app.set_version_flag("--version", std::string("kfw-cli ") + KFW_VERSION,
                       "print the version and exit");
  app.require_subcommand(0, 1);
  app.footer(std::string("\n") + value_grammar_help() + "\n" + kExitCodes);
}

// The top-level help, even when a command was parsed (App::help() would show that command's).
std::string top_help(const CLI::App& app) {
  return app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    for (const auto& l : o->get_lnames())
      names.push_back("--" + l);
    for (const auto& s : o->get_snames())
      names.push_back("-" + s);
  }
  return names;
}

// What was left over: an unknown command or option (with the nearest valid name), or an
// argument too many. Empty when nothing was left.
std::optional<Error> check_extras(const CLI::App& app) {
  const auto top = app.remaining(false);
  const auto subs = app.get_subcommands();
  if (!top.empty()) {
    const std::string& t = top.front();
    if (t.rfind("-", 0) == 0) {
      return Error{unknown_message("option", t.substr(0, t.find('=')), option_names(app)) +
                   " (try kfw-cli --help)"};
    }
    if (subs.empty()) {
      return Error{unknown_message("command", t, command_names(app)) + " (try kfw-cli --help)"};
    }
    return Error{"unexpected argument " + quote_token(t)};
  }
  for (const CLI::App* sub : subs) {
    const auto rest = sub->remaining(false);
    if (rest.empty()) continue;
    const std::string& t = rest.front();
    const std::string hint = " (try kfw-cli " + sub->get_name() + " --help)";
    if (t.rfind("-", 0) == 0 && t.size() > 1) {
      return Error{sub->get_name() + ": " +
                   unknown_message("option", t.substr(0, t.find('=')), option_names(*sub)) + hint};
    }
    return Error{sub->get_name() + ": unexpected argument " + quote_token(t) + hint};
  }
  return std::nullopt;
}

int dispatch(const Cli& cli, std::ostream& out, std::ostream& err) {
  const auto subs = cli.app.get_subcommands();
  if (subs.empty()) {
    err << top_help(cli.app);
    return kExitInvalid;
  }
  const std::string cmd = subs.front()->get_name();
  if (cmd == "help") {
    if (cli.topic.empty()) {
      out << top_help(cli.app);
      return kExitOk;
    }
    if (cli.topic == "grammar") {
      out << value_grammar_help();
      return kExitOk;
    }
    const CLI::App* sub = find_command(cli.app, cli.topic);
    if (!sub) {
      auto names = command_names(cli.app);
      names.push_back("grammar");
      return fail(err, Error{"help: " + unknown_message("command or topic", cli.topic, names)});
    }
    out << sub->help("kfw-cli");
    return kExitOk;
  }
  if (cmd == "simulate") return cmd_simulate(cli.simulate, out, err);
  if (cmd == "run") return cmd_run(cli.run, out, err);
  if (cmd == "gain") return cmd_gain(cli.gain, out, err);
  if (cmd == "tune") return cmd_tune(cli.tune, out, err);
  if (cmd == "sweep") return cmd_sweep(cli.sweep, out, err);
  if (cmd == "params") return cmd_params(cli.params, out, err);
  if (cmd == "metrics") return cmd_metrics(cli.metrics, out, err);
  if (cmd == "preset") return cmd_preset(cli.preset, out, err);
  if (cmd == "export-c") return cmd_export_c(cli.export_c, out, err);
  if (cmd == "list") return cmd_list(out);
  if (cmd == "merge") {
    if (cli.merge.resume) {
      if (!cli.merge.parts.empty() || cli.merge.output.out || cli.merge.output.metrics) {
        return fail(err,
                    Error{"--resume: lists what to resubmit; give no PART, --out or --metrics"});
      }
      return cmd_merge_resume(*cli.merge.resume, out, err);
    }
    if (cli.merge.parts.empty())
      return fail(err, Error{"merge: PART is required (or --resume DIR)"});
    return cmd_merge(cli.merge, out, err);
  }
  if (cmd == "inspect") return cmd_inspect(cli.inspect, out, err);
  if (cmd == "noise") return cmd_noise(cli.noise, out, err);
  if (cmd == "upgrade") return cmd_upgrade(cli.upgrade, out, err);
  return cmd_scenario(cmd, cli.scenario.at(cmd), out, err);
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  auto cli = std::make_unique<Cli>();
  declare(*cli);
  if (args.empty()) {
    err << top_help(cli->app);
    return kExitInvalid;
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them reversed
  try {
    cli->app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    out << cli->app.help();  // the help of the command given, if any
    return kExitOk;
  } catch (const CLI::CallForVersion& e) {
    out << e.what() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // A misspelt name explains the rest (a misspelt --out also makes --out "required").
    if (auto extra = check_extras(cli->app)) return fail(err, *extra);
    const auto subs = cli->app.get_subcommands();
    const std::string where = subs.empty() ? "" : subs.front()->get_name() + ": ";
    return fail(err, Error{where + e.what()});
  }
  if (auto extra = check_extras(cli->app)) return fail(err, *extra);
  return dispatch(*cli, out, err);
}

}  // namespace kfw
