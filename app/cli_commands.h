// The bodies of kfw-cli's commands. app/cli.cpp declares the commands and their options (CLI11)
// into the option structs of cli_options.h and calls these with them.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cli_options.h"
#include "core/dataset.h"
#include "core/expected.h"
#include "data/mapping.h"
#include "data/output.h"
#include "document/workspace.h"
#include "experiment/grammar.h"
#include "experiment/tuning.h"

namespace kfw {

// Each returns the process exit code (expected.h); errors go to `err` as one line.
int cmd_simulate(const SimulateArgs& a, std::ostream& out, std::ostream& err);
int cmd_run(const RunArgs& a, std::ostream& out, std::ostream& err);
int cmd_gain(const GainArgs& a, std::ostream& out, std::ostream& err);
int cmd_tune(const TuneArgs& a, std::ostream& out, std::ostream& err);
int cmd_sweep(const SweepArgs& a, std::ostream& out, std::ostream& err);
int cmd_params(const ParamsArgs& a, std::ostream& out, std::ostream& err);
int cmd_preset(const PresetArgs& a, std::ostream& out, std::ostream& err);
int cmd_export_c(const ExportCArgs& a, std::ostream& out, std::ostream& err);
int cmd_metrics(const MetricsArgs& a, std::ostream& out, std::ostream& err);
int cmd_list(std::ostream& out);
// run --seeds (app/cli_montecarlo.cpp): Monte Carlo over simulator seeds; a part with --shard.
int cmd_run_seeds(const RunArgs& a, std::ostream& out, std::ostream& err);
// merge PART...: parts of one kind ("montecarlo", ...) into one result.
int cmd_merge(const MergeArgs& a, std::ostream& out, std::ostream& err);
// merge --resume DIR (app/cli_resume.cpp): prints the array indices of DIR's missing or invalid
// parts ("3,7-9"; an empty line when every part is complete), each with its reason on `err`.
int cmd_merge_resume(const std::string& dir, std::ostream& out, std::ostream& err);
int cmd_inspect(const InspectArgs& a, std::ostream& out, std::ostream& err);
// noise: every linked column's white-noise level and the parameter values it proposes.
int cmd_noise(const NoiseArgs& a, std::ostream& out, std::ostream& err);
// A command a scenario offers (Scenario::commands()), e.g. `stats`.
int cmd_scenario(const std::string& cmd, ScenarioCommandArgs a, std::ostream& out,
                 std::ostream& err);

// A scenario name (its default preset) or a preset (a path or a name in presets/). The preset's
// notices (document/preset.h) are printed on `err`.
Expected<Workspace> open_any(const std::string& name, const std::optional<std::string>& data,
                             const std::vector<std::string>& sets, std::ostream& err);
// The workspace of a command: its preset (or scenario), --data, --set and the import options.
Expected<Workspace> open_workspace_for_cli(const TargetArgs& target, const DataArgs& data,
                                           std::ostream& err);
// "kfw-cli: notice: ..." on `err`, one line each.
void print_notices(const std::vector<std::string>& notices, std::ostream& err);
// upgrade FILE [--check] [--out F] (app/cli_upgrade.cpp): an old preset or session rewritten in
// the current form.
int cmd_upgrade(const UpgradeArgs& a, std::ostream& out, std::ostream& err);
// The files a command on this workspace reads: an output may not be one of them.
OutputSet outputs_for(const Workspace& ws);
// The preset's content hash for parts (FNV-1a 64 of its file; of its JSON when it has none): a
// preset edited between two shards makes their parts differ.
std::string preset_content_hash(const Workspace& ws);
// merge's handler for sweep parts ("kind": "sweep", app/cli_sweep.cpp).
Status merge_sweep_parts(const std::vector<nlohmann::json>& docs, const MergeArgs& a,
                         OutputSet& outs, std::ostream& out, std::ostream& err);

// tune --shard i/N: shard 1 keeps the start, shard i > 1 starts the searched keys at point i − 1
// of a Halton sequence in the search box (app/cli_tune_shard.cpp).
Status start_tune_shard(const Shard& shard, const std::vector<SearchParam>& params,
                        ParamValues& start);
// merge's handler for tune parts: the best start's preset (--out) and report.
Status merge_tune_parts(const std::vector<nlohmann::json>& docs, const MergeArgs& a,
                        OutputSet& outs, std::ostream& out, std::ostream& err);

// The --seeds set, refused with --data or a preset whose data come from a file (--seeds
// simulates each seed).
Expected<std::vector<long long>> seeds_for(const std::string& seeds,
                                           const std::optional<std::string>& data,
                                           const Workspace& ws);

// Writes "kfw-cli: MESSAGE" as one line (long tokens shortened) and returns the exit code.
int fail(std::ostream& err, const Error& e);

}  // namespace kfw
