#include "experiment/tune_part.h"

#include <cmath>

#include "data/json_check.h"

namespace kfw {

namespace jc = json_check;
using Json = nlohmann::json;

std::vector<double> halton_point(std::size_t k, std::size_t dim) {
  static constexpr unsigned kPrimes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31, 37, 41,
                                         43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97};
  std::vector<double> u(dim, 0.5);
  for (std::size_t d = 0; d < dim && d < std::size(kPrimes); ++d) {
    const double b = kPrimes[d];
    double f = 1.0, r = 0.0;
    for (std::size_t i = k; i > 0; i /= kPrimes[d]) {
      f /= b;
      r += f * static_cast<double>(i % kPrimes[d]);
    }
    u[d] = r;
  }
  return u;
}

nlohmann::ordered_json tune_part_to_json(const TunePart& p) {
  nlohmann::ordered_json j;
  j["kind"] = kTunePartKind;
  j["version"] = kTunePartVersion;
  j["scenario"] = p.scenario;
  j["source"] = p.source;
  j["preset_hash"] = p.preset_hash;
  j["values"] = p.values;
  j["shard"] = std::to_string(p.shard.index) + "/" + std::to_string(p.shard.count);
  j["start"] = p.start;
  j["objective"] = p.objective;
  if (std::isfinite(p.objective_value)) {
    j["objective_value"] = p.objective_value;
  } else {
    j["objective_value"] = nullptr;
  }
  j["best"] = p.best;
  j["preset_text"] = p.preset_text;
  j["report"] = p.report;
  return j;
}

Status check_tune_part(const Json& j, const std::string& where) {
  if (auto st = jc::object(j, where); !st) return st;
  const auto version = [](const Json& v, const std::string& w) -> Status {
    if (auto st = jc::integer(v, w, 1); !st) return st;
    if (v.get<double>() > kTunePartVersion) {
      return Error{w + ": written by a newer kfw (version " + v.dump() + ")"};
    }
    if (v.get<double>() < kTunePartVersion) return Error{w + ": tune parts start at version 2"};
    return Ok{};
  };
  if (auto st = jc::member(j, where, "version", version); !st) return st;
  for (const char* key :
       {"scenario", "source", "preset_hash", "shard", "objective", "preset_text"}) {
    if (auto st = jc::member(j, where, key, jc::string); !st) return st;
  }
  if (auto s = parse_shard(j.at("shard").get<std::string>(), "shard"); !s) {
    return Error{jc::at(where, "shard") + ": " + s.error()};
  }
  const auto values = [](const Json& v, const std::string& w) { return jc::number_map(v, w); };
  for (const char* key : {"values", "start", "best"}) {
    if (auto st = jc::member(j, where, key, values); !st) return st;
  }
  const auto objective = [](const Json& v, const std::string& w) -> Status {
    return v.is_null() ? Status{Ok{}} : jc::finite(v, w);
  };
  if (auto st = jc::member(j, where, "objective_value", objective); !st) return st;
  return jc::member(j, where, "report", jc::object);
}

namespace {

Shard shard_of(const Json& j) {
  return *parse_shard(j.at("shard").get<std::string>(), "shard");
}

// The objective value for ranking: NaN (no finite objective) ranks last.
double rank_of(const Json& j) {
  const Json& v = j.at("objective_value");
  return v.is_null() ? INFINITY : v.get<double>();
}

}  // namespace

Expected<std::size_t> best_tune_part(const std::vector<Json>& parts,
                                     const std::vector<std::string>& paths) {
  if (parts.empty()) return Error{"merge: no tune part"};
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (auto st = check_tune_part(parts[i], paths[i]); !st) return st.err();
  }
  const Json& first = parts.front();
  const std::size_t count = shard_of(first).count;
  std::vector<int> seen(count + 1, -1);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const Json& p = parts[i];
    for (const char* key : {"preset_hash", "values", "objective", "scenario"}) {
      if (p.at(key) != first.at(key)) {
        return Error{jc::at(paths[i], key) + ": differs from " + paths.front() +
                     " (parts of different tunings)"};
      }
    }
    const Shard s = shard_of(p);
    if (s.count != count) {
      return Error{jc::at(paths[i], "shard") + ": " + std::to_string(s.index) + "/" +
                   std::to_string(s.count) + " is not a shard of " + std::to_string(count)};
    }
    if (seen[s.index] >= 0) {
      return Error{paths[i] + ": shard " + std::to_string(s.index) + " is also in " +
                   paths[static_cast<std::size_t>(seen[s.index])]};
    }
    seen[s.index] = static_cast<int>(i);
  }
  std::string missing;
  for (std::size_t k = 1; k <= count; ++k) {
    if (seen[k] < 0) missing += (missing.empty() ? "" : ",") + std::to_string(k);
  }
  if (!missing.empty()) {
    return Error{"merge: shards " + missing + " of " + std::to_string(count) +
                 " are missing (kfw-cli merge --resume DIR lists what to resubmit)"};
  }
  std::size_t best = static_cast<std::size_t>(seen[1]);
  for (std::size_t k = 2; k <= count; ++k) {
    const auto i = static_cast<std::size_t>(seen[k]);
    if (rank_of(parts[i]) < rank_of(parts[best])) best = i;
  }
  if (!std::isfinite(rank_of(parts[best]))) {
    return failure("merge: no start found a finite objective");
  }
  return best;
}

}  // namespace kfw
