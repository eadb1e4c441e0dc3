// `kfw-cli stats PRESET --data FILE`: the analysis a model file's covariance blocks declare, as
// JSON — for each block the sample covariance of its series, the declared matrix beside it, the
// means and the count of samples (seed 004's eqs. 5–8 verification on a simulated log), and the
// outlier counts of the channels' outlier columns (null when the data has none).
#pragma once

#include <string>
#include <vector>

#include "core/expected.h"

namespace kfw::model {

struct ModelSpec;
struct ModelResult;

// The commands a model file may offer on the command line, declared once: the CLI lists them
// and ModelScenario::commands() offers those the file has the blocks for.
const std::vector<std::string>& model_commands();

// Whether the file offers `command` (stats: one covariance block or more).
bool model_offers(const ModelSpec& m, const std::string& command);

// The stats JSON (2-space indented) of a finished run on `source`.
std::string stats_json(const ModelSpec& m, const ModelResult& r, const std::string& source);

}  // namespace kfw::model
