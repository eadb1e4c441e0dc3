// The bodies of kfw-cli's commands. app/cli.cpp declares the commands and their options (CLI11)
// and calls these with the parsed arguments.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/expected.h"
#include "data/output.h"
#include "document/workspace.h"

namespace kfw {

// A sweep larger than this needs --max-points (README "Limits").
inline constexpr std::size_t kDefaultMaxPoints = 1000000;

// How every --data file is read (README "Importing logs"): applied over the preset's mapping.
struct ImportArgs {
  std::vector<std::string> map, unit, scale, offset, flip;  // ROLE=COLUMN, ROLE=UNIT, ...; ROLE
  std::optional<std::string> time, sep, mapping_file;       // COLUMN[:UNIT|:iso], SEP, FILE
  std::optional<std::string> header;                        // first, none, detect
  bool any() const {
    return !map.empty() || !unit.empty() || !scale.empty() || !offset.empty() || !flip.empty() ||
           time || sep || header || mapping_file;
  }
};

struct CliArgs {
  std::string target;  // PRESET: a preset file, a name in presets/, a scenario, or FILE.csv
  std::optional<std::string> data, out, metrics;
  std::optional<long long> seed;    // checked by the table's sim.seed range
  std::vector<std::string> sets;    // --set key=value
  std::vector<std::string> params;  // tune --params key,key
  std::vector<std::string> axes;    // sweep --param key=GRID
  std::string objective;            // tune: empty = the preset's default objective
  std::string metric;
  // tune (app/cli_tune.cpp)
  std::vector<std::string> data_all;  // every --data in order (tune: a tuning set; globs)
  std::string method = "bobyqa", aggregate = "mean";
  std::vector<std::string> lo, hi;  // --lo KEY=V, --hi KEY=V
  int budget = 400;
  double tol = 1e-6;
  bool markdown = false;                       // metrics --markdown
  std::size_t max_points = kDefaultMaxPoints;  // sweep --max-points
  std::optional<std::string> curve;            // gain --curve KEY
  std::size_t curve_points = 100;              // gain --points N
  std::optional<std::string> seeds, shard;     // run/sweep --seeds SET; run/sweep --shard i/N
  std::optional<std::string> out_dir;          // run --seeds --out-dir DIR
  bool table = false;                          // run --seeds, merge: a readable table
  std::vector<std::string> parts;              // merge PART...
  ImportArgs import;                           // --map, --unit, --time, ... (every --data)
  std::optional<std::string> inspect_preset;   // inspect FILE [PRESET]
  bool json = false;                           // inspect --json
};

// Each returns the process exit code (expected.h); errors go to `err` as one line.
int cmd_simulate(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_run(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_gain(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_tune(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_sweep(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_params(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_preset(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_metrics(const CliArgs& a, std::ostream& out, std::ostream& err);
int cmd_list(std::ostream& out);
// run --seeds (app/cli_montecarlo.cpp): Monte Carlo over simulator seeds; a part with --shard.
int cmd_run_seeds(const CliArgs& a, std::ostream& out, std::ostream& err);
// merge PART...: parts of one kind ("montecarlo", ...) into one result.
int cmd_merge(const CliArgs& a, std::ostream& out, std::ostream& err);
// A command a scenario offers (Scenario::commands()), e.g. `stats`.
int cmd_scenario(const std::string& cmd, CliArgs a, std::ostream& out, std::ostream& err);

// A scenario name (its default preset) or a preset (a path or a name in presets/).
Expected<Workspace> open_any(const std::string& name, const std::optional<std::string>& data,
                             const std::vector<std::string>& sets);
// The files a command on this workspace reads: an output may not be one of them.
OutputSet outputs_for(const Workspace& ws);
// merge's handler for sweep parts ("kind": "sweep", app/cli_tune.cpp).
Status merge_sweep_parts(const std::vector<nlohmann::json>& docs, const CliArgs& a, OutputSet& outs,
                         std::ostream& out, std::ostream& err);

// The --seeds set, refused with --data or a preset whose data come from a file (--seeds
// simulates each seed).
Expected<std::vector<long long>> seeds_for(const CliArgs& a, const Workspace& ws);
int cmd_inspect(const CliArgs& a, std::ostream& out, std::ostream& err);
// A command a scenario offers (Scenario::commands()), e.g. `stats`.
int cmd_scenario(const std::string& cmd, CliArgs a, std::ostream& out, std::ostream& err);

struct Workspace;
// The import options over the workspace's (the preset's) mapping: a --mapping file replaces the
// roles it names, then each option changes one field of one role. Unknown roles and units, bad
// numbers and a bad mapping file are errors naming the option or the file's key.
Status apply_import_args(const ImportArgs& imp, Workspace& ws);
// The workspace of a command: its preset (or scenario), --data, --set and the import options.
Expected<Workspace> open_workspace_for_cli(const CliArgs& a);

// Writes "kfw-cli: MESSAGE" as one line (long tokens shortened) and returns the exit code.
int fail(std::ostream& err, const Error& e);

}  // namespace kfw
