// kfw-cli sweep: grid sweeps that can be split into shards, and merge's handler for their parts
// ("kind": "sweep").
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_commands.h"
#include "cli_job.h"
#include "core/dataset.h"
#include "core/metrics.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/json_io.h"
#include "experiment/grammar.h"
#include "experiment/monte_carlo.h"
#include "experiment/sweep.h"
#include "experiment/sweep_part.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;
// Sweep documents keep their keys sorted (nlohmann::json), as they read back: a merged document
// is then byte for byte the one an unsharded sweep writes.
using Doc = nlohmann::json;

// A sweep as a JSON document: the grid, the metric and each point's value or why it stopped.
// Parts (one shard) and whole sweeps share it; no timings, no host names, so merging the parts
// of a sharded sweep gives the unsharded document byte for byte.
Doc sweep_document(const Workspace& ws, const std::vector<SweepAxis>& axes, const MetricSpec& spec,
                   const SweepResult& r, const Shard& shard, std::size_t total) {
  Doc j;
  j["kind"] = "sweep";
  j["version"] = kSweepPartVersion;
  j["scenario"] = ws.scenario->name();
  j["preset_hash"] = preset_content_hash(ws);
  j["metric"] = spec.key;
  j["direction"] = direction_name(spec.direction);
  if (spec.direction == Direction::kTarget) j["target"] = spec.target;
  j["axes"] = Doc::array();
  for (const auto& ax : axes)
    j["axes"].push_back(
        {{"key", ax.key}, {"lo", ax.lo}, {"hi", ax.hi}, {"n", ax.n}, {"log", ax.log}});
  j["base"] = ws.values;
  j["shard"] = {{"index", shard.index}, {"count", shard.count}};
  j["total_points"] = total;
  j["points"] = Doc::array();
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    Doc p = {{"index", r.indices.empty() ? i : r.indices[i]}, {"at", r.points[i]}};
    if (!r.errors[i].empty()) {
      p["error"] = r.errors[i];
    } else if (auto it = r.metrics[i].find(spec.key); it != r.metrics[i].end()) {
      p["value"] = it->second;
    }
    j["points"].push_back(p);
  }
  return j;
}

// A point's metric, or NaN where it is undefined (no "value", or null: a NaN as JSON writes it).
double point_value(const Doc& p) {
  const auto it = p.find("value");
  return it == p.end() || it->is_null() ? std::nan("") : it->get<double>();
}

// The summary printed by sweep and merge (best by the metric's direction, stopped runs), and
// the output (--out): a .json document or a .csv table.
Status finish_sweep(const Doc& doc, const MetricSpec& spec, const std::optional<std::string>& path,
                    OutputSet& outs, std::ostream& out, std::ostream& err) {
  const Doc& points = doc.at("points");
  const Doc& axes = doc.at("axes");
  const std::string metric = doc.at("metric");
  std::size_t best = points.size(), defined = 0, stopped_n = 0;
  Json stopped = Json::array();
  std::string first_error;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Doc& p = points[i];
    if (p.contains("error")) {
      ++stopped_n;
      if (first_error.empty()) first_error = p.at("error");
      Json at;
      for (std::size_t k = 0; k < axes.size(); ++k)
        at[axes[k].at("key").get<std::string>()] = p.at("at").at(k).get<double>();
      stopped.push_back({{"at", at}, {"error", p.at("error").get<std::string>()}});
      continue;
    }
    if (std::isnan(point_value(p))) continue;
    ++defined;
    if (best == points.size() || better(spec, point_value(p), point_value(points[best]))) {
      best = i;
    }
  }
  if (!points.empty() && stopped_n == points.size()) {
    return failure("sweep: every run stopped (first: " + first_error + ")");
  }
  if (best == points.size()) {
    return failure("sweep: " + quote_token(metric) + " has no value at any grid point");
  }
  if (!stopped.empty()) {
    err << "kfw-cli: warning: " << stopped.size() << " of " << points.size()
        << " runs stopped (listed under \"stopped\"; first: " << first_error << ")\n";
  }
  if (path) {
    const bool json = std::filesystem::path(*path).extension() == ".json";
    if (json) {
      if (auto st = stage_json(outs, *path, doc, 1); !st) return st;
    } else {
      auto table = std::make_shared<Dataset>();
      table->source = *path;
      for (const auto& ax : axes)
        table->add(ax.at("key").get<std::string>(), points.size());
      table->add(metric, points.size());
      for (std::size_t i = 0; i < points.size(); ++i) {
        for (std::size_t k = 0; k < axes.size(); ++k)
          table->columns[k][i] = points[i].at("at").at(k).get<double>();
        table->columns[axes.size()][i] = point_value(points[i]);
      }
      auto write = [table](OutputStream& os) {
        return write_csv_stream(os, table_columns(*table), table->rows());
      };
      if (auto st = outs.stage_stream(*path, write); !st) return st;
    }
  }
  if (auto st = outs.commit(); !st) return st;
  Json j;
  j["metric"] = metric;
  j["direction"] = doc.at("direction").get<std::string>();
  if (doc.contains("target")) j["target"] = doc.at("target").get<double>();
  j["points"] = points.size();
  j["points_defined"] = defined;
  if (doc.contains("seeds")) j["seeds"] = doc.at("seeds").get<std::size_t>();
  j["best"] = points[best].at("value").get<double>();
  for (std::size_t k = 0; k < axes.size(); ++k)
    j["best_at"][axes[k].at("key").get<std::string>()] = points[best].at("at").at(k).get<double>();
  j["stopped"] = stopped;
  out << j.dump(2) << "\n";
  return Ok{};
}

}  // namespace

int cmd_sweep(const SweepArgs& a, std::ostream& out, std::ostream& err) {
  auto ws = open_workspace_for_cli(a.target, a.data, err);
  if (!ws) return fail(err, ws.err());
  std::optional<std::vector<long long>> seeds;
  if (a.seeds) {
    auto set = seeds_for(*a.seeds, a.data.file, *ws);
    if (!set) return fail(err, set.err());
    seeds = std::move(*set);
    if (a.shard)
      return fail(err, Error{"--shard: not with --seeds on sweep (shard the grid alone)"});
  }
  std::vector<SweepAxis> axes;
  for (const auto& t : a.axes) {
    auto ax = parse_sweep_axis(ws->scenario->params(), t);
    if (!ax) return fail(err, ax.err());
    axes.push_back(*ax);
  }
  Shard shard;
  if (a.shard) {
    auto s = parse_shard(*a.shard, "--shard");
    if (!s) return fail(err, s.err());
    shard = *s;
    if (!a.out || std::filesystem::path(*a.out).extension() != ".json") {
      return fail(err, Error{"--shard: write the part with --out PART.json (kfw-cli merge reads "
                             "the parts)"});
    }
  }
  // Refused at once, before any run: the points of this shard (the whole grid without one).
  const std::size_t most = std::numeric_limits<std::size_t>::max();
  const std::size_t limit =
      a.max_points >= most / (shard.count + 1) ? most : (a.max_points + 1) * shard.count;
  const auto total = grid_size(axes, limit);
  if (!total || shard_size(*total, shard) > a.max_points) {
    return fail(
        err, Error{"--param: the grid has more than " + std::to_string(a.max_points) + " points" +
                   (a.shard ? " in this shard" : "") + "; raise --max-points to run it"});
  }
  OutputSet outs = outputs_for(*ws);
  if (a.out) {
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
  }
  auto d = load_dataset(*ws);
  if (!d) return fail(err, d.err());
  // One run at the base values tells which metrics this scenario and dataset produce.
  // (A base run that stops numerically is no reason not to sweep: grid points may run.)
  auto probe = ws->scenario->run(*d, ws->values);
  if (!probe && probe.exit_code() != kExitFailed) return fail(err, probe.err());
  const RunResult* base = probe ? probe->get() : nullptr;
  const std::string& metric = a.metric;
  const auto keys = metric_keys(*ws->scenario, base);
  if (std::find(keys.begin(), keys.end(), metric) == keys.end()) {
    return fail(err, Error{"--metric: " + unknown_message("metric", metric, keys)});
  }
  if (base) {
    if (auto u = base->undefined.find(metric); u != base->undefined.end()) {
      return fail(err, Error{"--metric: " + quote_token(metric) +
                             " is undefined on this dataset (" + u->second + ")"});
    }
  }
  const MetricSpec spec = describe_metric(*ws->scenario, metric, base);
  // With --seeds each point is scored by the metric's mean over the seeds.
  CliJob job(err, a.progress, "points");
  const std::size_t in_part = shard_size(*total, shard);
  MonteCarloOptions per_point;
  per_point.threads = a.jobs;
  per_point.cancel = job.cancel();
  auto r = seeds ? sweep_over_seeds(*ws->scenario, ws->values, axes, *seeds, per_point)
                 : sweep(*ws->scenario, *d, ws->values, axes, a.jobs, job.cancel(), shard,
                         [&job, in_part](std::size_t done) { job.progress(done, in_part); });
  job.finish();
  if (const int code = job.interrupted()) return fail(err, Error{job.interrupted_message(), code});
  if (!r) return fail(err, r.err());
  Doc doc = sweep_document(*ws, axes, spec, *r, shard, *total);
  if (seeds) doc["seeds"] = seeds->size();
  if (auto st = finish_sweep(doc, spec, a.out, outs, out, err); !st) return fail(err, st.err());
  return kExitOk;
}

namespace {

// Merges the parts of a sharded sweep (experiment/sweep_part.h) and prints and writes the result
// as an unsharded sweep does.
Status merge_sweep_impl(const std::vector<nlohmann::json>& parts, const MergeArgs& a,
                        OutputSet& outs, std::ostream& out, std::ostream& err) {
  if (a.output.out) {
    if (auto st = outs.add(*a.output.out, "--out"); !st) return st;
  }
  auto doc = merge_sweep_documents(parts, a.parts);
  if (!doc) return doc.err();
  const Doc& first = *doc;
  MetricSpec spec;
  spec.key = first.at("metric");
  // The direction and target the parts were judged by (the spec comes with the part).
  for (auto d : {Direction::kLower, Direction::kHigher, Direction::kTarget, Direction::kNone}) {
    if (first.at("direction") == direction_name(d)) spec.direction = d;
  }
  if (first.contains("target")) spec.target = first.at("target").get<double>();
  return finish_sweep(first, spec, a.output.out, outs, out, err);
}

}  // namespace

Status merge_sweep_parts(const std::vector<nlohmann::json>& parts, const MergeArgs& a,
                         OutputSet& outs, std::ostream& out, std::ostream& err) {
  try {
    return merge_sweep_impl(parts, a, outs, out, err);
  } catch (const nlohmann::json::exception& e) {
    // Past the schema (check_sweep_part): a bug, not the part; still no abort.
    return Error{"merge: a part is malformed (" + std::string(e.what()) + ")"};
  }
}

}  // namespace kfw
