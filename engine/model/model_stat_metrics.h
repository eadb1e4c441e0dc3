// A model file's named metrics (version 2, issue 28; presets/models/README.md, "Named metrics"):
// a statistic of one of the run's series — a derived series or a grid axis's estimate, centre,
// ends or span — over the rows from a time on, under the name the file gives (seed 001's
// `refraction_err_max_deg` over t ≥ 10 s).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/metrics.h"
#include "core/param_spec.h"
#include "core/scenario.h"
#include "model/expression.h"

namespace kfw::model {

struct ModelSpec;
struct ModelResult;
namespace detail {
class Reader;
}

enum class Stat { kRms, kMaxAbs, kFinal, kMin, kMax, kMean };

struct StatMetricSpec {
  std::string name, label, unit, description;
  std::string of;  // "derived.NAME", "imm.PARAM", "imm.PARAM.centre|low|high|span"
  Stat stat = Stat::kRms;
  Expr from;  // s, parameters only; empty text: from the first row
  Direction direction = Direction::kNone;
};

// The "metrics" block, after the derived quantities and the modes (its series must exist).
Status parse_stat_metrics(const detail::Reader& p, const nlohmann::json& block, ModelSpec& m);
std::vector<MetricSpec> stat_metric_specs(const ModelSpec& spec);
// After add_derived and add_imm_metrics: each named metric, or why it is undefined.
void add_stat_metrics(const ModelSpec& spec, const ParamValues& values, ModelResult& r);

// model.metrics_from (version 2): the first row at or after that time (`at`, s; 0 and −∞ when the
// file has no such key), from which the standard accuracy and consistency metrics count (seed
// 001's "metrics over t ≥ 10 s"); the innovation channels and the NEES from that row on.
std::size_t metrics_from_row(const ModelSpec& spec, const ParamValues& values,
                             const std::vector<double>& t, double& at);
std::vector<InnovationChannel> channels_from(std::vector<InnovationChannel> channels,
                                             std::size_t from);
NeesSeries nees_from(NeesSeries nees, std::size_t from);

}  // namespace kfw::model
