// `kfw-cli run PRESET --seeds SET` (Monte Carlo over simulator seeds, sharded like sweeps) and
// `kfw-cli merge PART...` (parts of any kind, dispatched on their "kind").
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_commands.h"
#include "cli_job.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/json_io.h"
#include "data/output.h"
#include "document/workspace.h"
#include "experiment/grammar.h"
#include "experiment/monte_carlo.h"
#include "experiment/tune_part.h"

namespace kfw {

namespace {

// The summary on stdout (table or JSON without per-step arrays) and, with --metrics, the full
// JSON (per-step ANEES_k / ANIS_k and bounds) staged for writing.
Status report(const MonteCarloSummary& s, const std::optional<std::string>& metrics, bool table,
              OutputSet& outs, std::ostream& out, std::ostream& err) {
  for (const auto& r : s.stopped)
    err << "kfw-cli: warning: seed " << r.seed << " stopped: " << one_line(r.error) << "\n";
  if (metrics) {
    if (auto st = stage_json(outs, *metrics, summary_to_json(s, true), 2); !st) return st;
  }
  if (auto st = outs.commit(); !st) return st;
  if (table) {
    out << summary_table(s);
  } else {
    out << summary_to_json(s, false).dump(2) << "\n";
  }
  return Ok{};
}

// A run with no completed seed has nothing to summarise (exit 1, the first error named).
Status require_completed(const MonteCarloSummary& s) {
  if (s.completed > 0 || s.stopped.empty()) return Ok{};
  return failure("every run stopped (first: seed " + std::to_string(s.stopped.front().seed) + ": " +
                 s.stopped.front().error + ")");
}

Status merge_montecarlo(const std::vector<nlohmann::json>& docs, const MergeArgs& a,
                        OutputSet& outs, std::ostream& out, std::ostream& err) {
  std::vector<MonteCarloPart> parts;
  for (std::size_t i = 0; i < docs.size(); ++i) {
    auto p = part_from_json(docs[i], a.parts[i]);
    if (!p) return p.err();
    parts.push_back(std::move(*p));
  }
  std::vector<std::string> notes;
  auto merged = merge_montecarlo_parts(parts, a.parts, &notes);
  if (!merged) return merged.err();
  for (const auto& n : notes)
    err << "kfw-cli: warning: " << one_line(n) << "\n";
  // --out: the merged part itself (one shard of all the seeds), mergeable again.
  if (a.output.out) {
    if (auto st = outs.add(*a.output.out, "--out"); !st) return st;
    if (auto st = stage_json(outs, *a.output.out, part_to_json(*merged), 2); !st) return st;
  }
  const MonteCarloSummary s = summarize_monte_carlo(*merged);
  if (auto st = require_completed(s); !st) return st;
  return report(s, a.output.metrics, a.table, outs, out, err);
}

// What `merge` does with the parts of one kind.
using MergeHandler = Status (*)(const std::vector<nlohmann::json>&, const MergeArgs&, OutputSet&,
                                std::ostream&, std::ostream&);
const std::map<std::string, MergeHandler>& merge_handlers() {
  static const std::map<std::string, MergeHandler> handlers = {
      {kMonteCarloKind, &merge_montecarlo},
      {"sweep", &merge_sweep_parts},       // app/cli_sweep.cpp
      {kTunePartKind, &merge_tune_parts},  // app/cli_tune_shard.cpp
  };
  return handlers;
}

}  // namespace

Expected<std::vector<long long>> seeds_for(const std::string& set,
                                           const std::optional<std::string>& data,
                                           const Workspace& ws) {
  auto seeds = parse_int_set(set, "--seeds");
  if (!seeds) return seeds.err();
  if (data) return Error{"--seeds simulates each seed; it cannot be used with --data"};
  if (ws.data_path) {
    return Error{ws.preset.path + ": data: the preset's data come from " + *ws.data_path +
                 "; --seeds simulates (use a preset without \"data\")"};
  }
  return seeds;
}

int cmd_run_seeds(const RunArgs& a, std::ostream& out, std::ostream& err) {
  const RunSeedsArgs& mc = a.seeds;
  const OutputArgs& o = a.output;
  auto ws = open_any(a.target.preset, a.data.file, a.target.sets, err);
  if (!ws) return fail(err, ws.err());
  auto seeds = seeds_for(*mc.seeds, a.data.file, *ws);
  if (!seeds) return fail(err, seeds.err());
  Shard shard;
  if (mc.shard) {
    auto s = parse_shard(*mc.shard, "--shard");
    if (!s) return fail(err, s.err());
    shard = *s;
    if (!o.out)
      return fail(err, Error{"--shard: needs --out PART.json (kfw-cli merge joins them)"});
  }
  OutputSet outs;
  outs.add_input(ws->preset.path);
  if (o.out) {
    if (auto st = outs.add(*o.out, "--out"); !st) return fail(err, st.err());
  }
  if (o.metrics) {
    if (auto st = outs.add(*o.metrics, "--metrics"); !st) return fail(err, st.err());
  }
  std::vector<std::pair<long long, std::string>> per_seed;  // seed, estimates path
  if (mc.out_dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(*mc.out_dir, ec)) {
      return fail(err, Error{"--out-dir: " + *mc.out_dir + ": not a directory"});
    }
    for (std::size_t i = 0; i < seeds->size(); ++i) {
      if (!in_shard(i, shard)) continue;
      const long long seed = (*seeds)[i];
      const std::string path =
          (std::filesystem::path(*mc.out_dir) / ("seed_" + std::to_string(seed) + ".csv")).string();
      if (auto st = outs.add(path, "--out-dir"); !st) return fail(err, st.err());
      per_seed.emplace_back(seed, path);
    }
  }
  MonteCarloOptions opt;
  opt.keep_results = mc.out_dir.has_value();
  opt.threads = mc.jobs;
  CliJob job(err, mc.progress, "seeds");
  opt.cancel = job.cancel();
  opt.progress = [&job](std::size_t done, std::size_t total) { job.progress(done, total); };
  auto part = run_monte_carlo(*ws->scenario, ws->values, *seeds, shard, opt);
  job.finish();
  if (const int code = job.interrupted()) return fail(err, Error{job.interrupted_message(), code});
  if (!part) return fail(err, part.err());
  part->source = a.target.preset;
  part->preset_hash = preset_content_hash(*ws);
  for (const auto& [seed, path] : per_seed) {
    for (const auto& r : part->runs) {
      if (r.seed != seed || !r.result) continue;
      const RunResult* res = r.result.get();
      auto write = [res, view = res->table_view()](OutputStream& os) {
        return write_csv_stream(os, view, res->steps());
      };
      if (auto st = outs.stage_stream(path, write); !st) return fail(err, st.err());
    }
  }
  if (o.out) {
    if (auto st = stage_json(outs, *o.out, part_to_json(*part), 1); !st) return fail(err, st.err());
  }
  const MonteCarloSummary s = summarize_monte_carlo(*part);
  if (mc.shard) {
    // A part is written even when its seeds all stopped: the merge decides.
    if (auto st = outs.commit(); !st) return fail(err, st.err());
    out << "wrote " << *o.out << " (shard " << shard.index << "/" << shard.count << ": "
        << part->runs.size() << " of " << part->seeds.size() << " seeds, " << s.stopped.size()
        << " stopped)\n";
    return kExitOk;
  }
  if (auto st = require_completed(s); !st) return fail(err, st.err());
  if (auto st = report(s, o.metrics, mc.table, outs, out, err); !st) return fail(err, st.err());
  return kExitOk;
}

int cmd_merge(const MergeArgs& a, std::ostream& out, std::ostream& err) {
  OutputSet outs;
  for (const auto& p : a.parts)
    outs.add_input(p);
  if (a.output.metrics) {
    if (auto st = outs.add(*a.output.metrics, "--metrics"); !st) return fail(err, st.err());
  }
  std::vector<nlohmann::json> docs;
  std::string kind;
  std::vector<std::string> kinds;
  for (const auto& [k, h] : merge_handlers())
    kinds.push_back(k);
  for (const auto& path : a.parts) {
    auto doc = read_json_document(path, "part");
    if (!doc) return fail(err, doc.err());
    const auto kv = doc->is_object() ? doc->find("kind") : doc->end();
    if (doc->is_object() && kv != doc->end() && !kv->is_string()) {
      return fail(err, Error{path + ": kind: expected a string, found " + json_type_name(*kv)});
    }
    const std::string k = doc->is_object() && kv != doc->end() ? kv->get<std::string>() : "";
    if (!merge_handlers().count(k)) {
      return fail(err,
                  Error{path + ": kind: " +
                        (k.empty() ? std::string("missing") : unknown_message("kind", k, kinds))});
    }
    if (!kind.empty() && k != kind) {
      return fail(err, Error{path + ": kind '" + k + "' differs from " + a.parts.front() + "'s '" +
                             kind + "'"});
    }
    kind = k;
    docs.push_back(std::move(*doc));
  }
  if (auto st = merge_handlers().at(kind)(docs, a, outs, out, err); !st) return fail(err, st.err());
  return kExitOk;
}

}  // namespace kfw
