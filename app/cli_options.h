// The options of kfw-cli's commands: one struct per command, which app/cli.cpp declares the
// command's options into (CLI11) and the command's body (cli_commands.h) reads. What several
// commands share (the preset and --set, --data and the import options, the outputs) is a small
// struct of its own that they compose.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "document/import_args.h"

namespace kfw {

// A sweep larger than this needs --max-points (README "Limits").
inline constexpr std::size_t kDefaultMaxPoints = 1000000;

// PRESET and the --set assignments over its values.
struct TargetArgs {
  std::string preset;             // a preset file, a name in presets/, a scenario (or FILE.csv)
  std::vector<std::string> sets;  // --set KEY=VALUE
};

// How every --data file is read (README "Importing logs"): applied over the preset's mapping.
// --data FILE.csv (default: the preset's, else simulated) and how it is read.
struct DataArgs {
  std::optional<std::string> file;
  ImportArgs import;
};

// The files a command writes: --out and --metrics.
struct OutputArgs {
  std::optional<std::string> out, metrics;
};

struct SimulateArgs {
  TargetArgs target;
  std::optional<long long> seed;  // --seed: checked by the table's sim.seed range
  std::string out;                // --out FILE.csv (required)
};

// run --seeds SET: Monte Carlo over simulator seeds (app/cli_montecarlo.cpp).
struct RunSeedsArgs {
  std::optional<std::string> seeds;    // --seeds SET
  std::optional<std::string> shard;    // --shard i/N: a part into --out
  std::optional<std::string> out_dir;  // --out-dir DIR: one estimates file per seed
  bool table = false;                  // --table: a readable table instead of JSON
  bool progress = false;               // --progress: progress on stderr even when not a terminal
  int jobs = 0;                        // --jobs N: worker threads; 0: every core it may use
};

struct RunArgs {
  TargetArgs target;
  DataArgs data;
  OutputArgs output;  // --out: the estimates (--seeds: the part); --metrics
  RunSeedsArgs seeds;
};

// merge PART...: parts of one kind ("montecarlo", "sweep", "tune") into one result; --resume DIR:
// which parts of DIR are missing or invalid.
struct MergeArgs {
  std::vector<std::string> parts;
  OutputArgs output;                  // --out: the merged sweep; --metrics: the merged result
  bool table = false;                 // --table
  std::optional<std::string> resume;  // --resume DIR
};

struct GainArgs {
  TargetArgs target;
  DataArgs data;
  std::optional<std::string> curve;  // --curve KEY
  std::size_t points = 100;          // --points N of the curve
  std::optional<std::string> x;      // --x NAME: a steady-state quantity as the curve's x too
};

struct TuneArgs {
  TargetArgs target;
  std::vector<std::string> data;    // every --data in order (a tuning set; globs)
  ImportArgs import;                // the same mapping for every log of the tuning set
  std::vector<std::string> params;  // --params KEY,KEY; empty: the preset's tunable keys
  std::string objective;            // empty: the preset's default objective
  std::string method = "bobyqa", aggregate = "mean";
  std::vector<std::string> lo, hi;  // --lo KEY=V, --hi KEY=V
  int budget = 400;
  double tol = 1e-6;
  std::optional<std::string> seeds;  // --seeds SET: a tuning set of simulated datasets
  std::optional<std::string> out;    // --out FILE.json: the tuned preset
  bool progress = false;             // --progress
  int jobs = 0;                      // --jobs N: worker threads; 0: every core it may use
  std::optional<std::string> shard;  // --shard i/N: one start, a part into --out
};

struct SweepArgs {
  TargetArgs target;
  DataArgs data;
  std::vector<std::string> axes;     // --param KEY=GRID
  std::string metric;                // --metric NAME
  std::optional<std::string> out;    // --out FILE.csv|FILE.json
  std::optional<std::string> seeds;  // --seeds SET: each point scored by the mean over seeds
  std::size_t max_points = kDefaultMaxPoints;
  std::optional<std::string> shard;  // --shard i/N
  bool progress = false;             // --progress
  int jobs = 0;                      // --jobs N: worker threads; 0: every core it may use
};

struct ParamsArgs {
  TargetArgs target;
};

// export-c PRESET: the filter as C (engine/codegen/c_export.h).
struct ExportCArgs {
  TargetArgs target;
  DataArgs data;                      // --data: --steady's interval is its median
  std::string out_dir = ".";          // --out-dir DIR
  std::optional<std::string> prefix;  // --prefix NAME; default: the preset's file stem
  bool single = false;                // --float
  bool steady = false;                // --steady
  bool params_struct = false;         // --params-struct: the parameters in NAME_params
  std::optional<double> dt;           // --dt S: --steady's interval
};

struct PresetArgs {
  TargetArgs target;
  std::string out;  // --out FILE.json (required)
};

struct MetricsArgs {
  std::string preset;
  bool markdown = false;  // --markdown: the README's tables
};

// inspect FILE [PRESET]
struct InspectArgs {
  std::string file;
  std::optional<std::string> preset;  // guess the roles of this preset or scenario
  ImportArgs import;
  bool json = false;  // --json
};

// noise PRESET [--data F]: the linked columns' noise and the parameter values it proposes.
struct NoiseArgs {
  TargetArgs target;
  DataArgs data;
};

// upgrade FILE: an old preset or session in the current form (app/cli_upgrade.cpp).
struct UpgradeArgs {
  std::string file;
  bool check = false;              // --check: write nothing; exit 0 current, 1 would change
  std::optional<std::string> out;  // --out FILE: write there (FILE untouched, no .bak)
};

// A command a scenario offers (Scenario::commands()), e.g. `stats`.
struct ScenarioCommandArgs {
  TargetArgs target;  // PRESET, or FILE.csv when one scenario offers the command
  DataArgs data;
};

}  // namespace kfw
