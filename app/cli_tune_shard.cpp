// tune --shard i/N (one start of a tuning per Slurm array task, experiment/tune_part.h) and
// merge's handler for tune parts: the best start's tuned preset.
#include <cmath>
#include <nlohmann/json.hpp>

#include "cli_commands.h"
#include "data/json_io.h"
#include "experiment/tune_part.h"
#include "experiment/tuning.h"

namespace kfw {

Status start_tune_shard(const Shard& shard, const std::vector<SearchParam>& params,
                        ParamValues& start) {
  if (shard.index == 1) return Ok{};  // the preset's own start
  const auto u = halton_point(shard.index - 1, params.size());
  for (std::size_t i = 0; i < params.size(); ++i) {
    const SearchParam& p = params[i];
    start[p.key] =
        p.log ? std::pow(10.0, std::log10(p.lo) + u[i] * (std::log10(p.hi) - std::log10(p.lo)))
              : p.lo + u[i] * (p.hi - p.lo);
  }
  return Ok{};
}

Status merge_tune_parts(const std::vector<nlohmann::json>& docs, const MergeArgs& a,
                        OutputSet& outs, std::ostream& out, std::ostream&) {
  if (a.table) return Error{"--table: not for tune parts (merge prints the best start's report)"};
  auto best = best_tune_part(docs, a.parts);
  if (!best) return best.err();
  const nlohmann::json& part = docs[*best];
  if (a.output.out) {
    if (auto st = outs.add(*a.output.out, "--out"); !st) return st;
    if (auto st = outs.stage(*a.output.out, part.at("preset_text").get<std::string>()); !st) {
      return st;
    }
  }
  nlohmann::ordered_json report = part.at("report");
  report["shard"] = part.at("shard");
  report["starts"] = docs.size();
  report["start"] = part.at("start");
  if (a.output.metrics) {
    if (auto st = stage_json(outs, *a.output.metrics, report, 2); !st) return st;
  }
  if (auto st = outs.commit(); !st) return st;
  out << report.dump(2) << "\n";
  return Ok{};
}

}  // namespace kfw
