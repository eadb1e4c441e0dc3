// A tune part ("kind": "tune", written by `kfw-cli tune --shard i/N`): one independent start of
// a tuning, for a Slurm array (docs/cluster.md). Shard 1 starts from the preset's values, shard
// i > 1 from point i − 1 of a Halton sequence in the search box (log10 for log-scale keys), so N
// tasks search N starts at once; `merge` keeps the best and writes its tuned preset. The part
// carries the hardening issue's part schema (version 2: the preset's content hash and every
// value), and is checked like the other parts before any value is read.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"
#include "experiment/grammar.h"

namespace kfw {

inline constexpr const char* kTunePartKind = "tune";
inline constexpr int kTunePartVersion = 2;

// Point `k` (from 1) of the Halton sequence in [0, 1)^dim (bases 2, 3, 5, 7, …).
std::vector<double> halton_point(std::size_t k, std::size_t dim);

// What one start found, as the part stores it.
struct TunePart {
  std::string scenario, source, preset_hash;
  ParamValues values;  // every value the tuning started from (the preset with --set)
  Shard shard;
  ParamValues start;              // the searched keys at this shard's start
  std::string objective;          // the objective's name
  double objective_value = 0.0;   // lower is better (NaN: no finite objective)
  ParamValues best;               // every value at this start's optimum
  std::string preset_text;        // the tuned preset, as `tune --out` writes it
  nlohmann::ordered_json report;  // what `tune` prints
};

nlohmann::ordered_json tune_part_to_json(const TunePart& p);
// The part against its schema (types, the shard, finite values), then read. `where` names it.
Status check_tune_part(const nlohmann::json& j, const std::string& where);

// The parts of one tuning (same preset hash, values, objective and N; every shard once): the index
// in `parts` of the best (lowest objective; the lowest shard on a tie). Errors name the file.
Expected<std::size_t> best_tune_part(const std::vector<nlohmann::json>& parts,
                                     const std::vector<std::string>& paths);

}  // namespace kfw
