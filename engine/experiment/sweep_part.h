// A sweep part ("kind": "sweep", written by `kfw-cli sweep --shard`) as merge reads it: the
// schema check of one part and the combination of the parts of one sweep. A part is written by
// another run, copied and possibly edited, so nothing in it is trusted: each node is checked for
// its type and range, each point's coordinates against the part's own grid, before any value is
// read (issue 29).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/expected.h"

namespace kfw {

inline constexpr int kSweepPartVersion = 2;  // written; 1 and 2 are read (2: preset_hash)

// One part against the schema: types, counts, the shard, and every point's index (in the grid,
// in its shard) and coordinates (those of its index on the axes' grid). `where` names the file.
Status check_sweep_part(const nlohmann::json& part, const std::string& where);

// The parts of one sweep (each checked) combined into the document an unsharded sweep writes:
// the same grid, metric, base values and preset, every shard once, every point once.
Expected<nlohmann::json> merge_sweep_documents(const std::vector<nlohmann::json>& parts,
                                               const std::vector<std::string>& paths);

}  // namespace kfw
