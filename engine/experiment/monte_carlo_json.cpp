// Monte Carlo parts as files, their merge, and the summary as JSON and as a table.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <tuple>

#include "core/suggest.h"
#include "data/json_check.h"
#include "data/json_io.h"
#include "experiment/monte_carlo.h"

namespace kfw {

namespace {

using OJson = nlohmann::ordered_json;
using Json = nlohmann::json;

OJson sums_to_json(const StepSums& s) {
  return OJson{{"name", s.name}, {"label", s.label},   {"dof", s.dof},
               {"sum", s.sum},   {"sum_sq", s.sum_sq}, {"count", s.count}};
}

Expected<StepSums> sums_from_json(const Json& j, const std::string& where) {
  if (!j.is_object()) return Error{where + ": must be an object"};
  StepSums s;
  try {
    s.name = j.at("name").get<std::string>();
    s.label = j.value("label", s.name);
    s.dof = j.at("dof").get<double>();
    s.sum = j.at("sum").get<std::vector<double>>();
    s.sum_sq = j.at("sum_sq").get<std::vector<double>>();
    s.count = j.at("count").get<std::vector<std::size_t>>();
  } catch (const Json::exception& e) {
    return Error{where + ": " + e.what()};
  }
  if (s.sum.size() != s.count.size() || s.sum_sq.size() != s.count.size()) {
    return Error{where + ": sum, sum_sq and count must have the same length"};
  }
  if (!(s.dof > 0.0)) return Error{where + ".dof: must be positive"};
  return s;
}

std::string shard_text(const Shard& s) {
  return std::to_string(s.index) + "/" + std::to_string(s.count);
}

std::string fixed(double v, int digits = 6) {
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

OJson consistency_json(const ConsistencySummary& c) {
  return OJson{{"label", c.label},
               {"dof", c.dof},
               {"runs", c.runs},
               {"bounds", {c.lo, c.hi}},
               {"time_average", c.time_average},
               {"inside", c.inside}};
}

}  // namespace

nlohmann::ordered_json part_to_json(const MonteCarloPart& p) {
  OJson j;
  j["kind"] = kMonteCarloKind;
  j["version"] = kMonteCarloPartVersion;
  j["scenario"] = p.scenario;
  j["source"] = p.source;
  j["preset_hash"] = p.preset_hash;
  j["values"] = p.values;
  j["seeds"] = p.seeds;
  j["shard"] = shard_text(p.shard);
  OJson runs = OJson::array();
  for (const auto& r : p.runs) {
    OJson one;
    one["seed"] = r.seed;
    if (r.stopped()) {
      one["error"] = r.error;
    } else {
      one["metrics"] = r.metrics;
      one["undefined"] = r.undefined;
      if (!r.warnings.empty()) one["warnings"] = r.warnings;
    }
    runs.push_back(std::move(one));
  }
  j["runs"] = std::move(runs);
  j["t"] = p.t;
  j["nees"] = p.nees ? sums_to_json(*p.nees) : OJson();
  OJson nis = OJson::array();
  for (const auto& s : p.nis)
    nis.push_back(sums_to_json(s));
  j["nis"] = std::move(nis);
  if (p.error && p.variance) {
    j["error"] = sums_to_json(*p.error);
    j["variance"] = sums_to_json(*p.variance);
    j["error_unit"] = p.error_unit;
  }
  return j;
}

namespace {

namespace jc = json_check;

// Per-step sums (NEES, NIS, error, variance): counts whole, 0 ≤ count ≤ the part's runs, sums
// finite, sums of squares ≥ 0, the three arrays of one length.
Status check_sums(const Json& j, const std::string& where, std::size_t runs) {
  if (auto st = jc::object(j, where); !st) return st;
  if (auto st = jc::member(j, where, "name", jc::string); !st) return st;
  if (auto st = jc::member(j, where, "label", jc::string, true); !st) return st;
  const auto positive = [](const Json& v, const std::string& w) {
    return jc::finite(v, w, 1e-300);
  };
  if (auto st = jc::member(j, where, "dof", positive); !st) return st;
  const auto any = [](const Json& v, const std::string& w) { return jc::finite_array(v, w); };
  const auto squares = [](const Json& v, const std::string& w) {
    return jc::finite_array(v, w, 0.0);
  };
  if (auto st = jc::member(j, where, "sum", any); !st) return st;
  if (auto st = jc::member(j, where, "sum_sq", squares); !st) return st;
  if (auto st = jc::member(j, where, "count", jc::count_array); !st) return st;
  const std::size_t n = j.at("count").size();
  for (const char* k : {"sum", "sum_sq"}) {
    if (j.at(k).size() != n)
      return Error{jc::at(where, k) + ": " + std::to_string(j.at(k).size()) +
                   " values, \"count\" has " + std::to_string(n)};
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (j.at("count")[k].get<double>() > static_cast<double>(runs)) {
      return Error{jc::at(where, "count") + "[" + std::to_string(k) +
                   "]: " + j.at("count")[k].dump() + " is more than the part's " +
                   std::to_string(runs) + " runs"};
    }
  }
  return Ok{};
}

// A run's metric: finite, and small enough that its square sums without overflow.
Status check_metrics(const Json& j, const std::string& where) {
  if (auto st = jc::number_map(j, where); !st) return st;
  for (const auto& [k, v] : j.items()) {
    if (std::abs(v.get<double>()) > 1e150) {
      return Error{jc::at(where, k) + ": " + v.dump() +
                   " is too large to average (|value| > 1e150)"};
    }
  }
  return Ok{};
}

Status check_seed(const Json& v, const std::string& where) {
  return jc::integer(v, where, 0.0, 1e15);
}

Status check_run(const Json& r, const std::string& where) {
  if (auto st = jc::object(r, where); !st) return st;
  if (auto st = jc::member(r, where, "seed", check_seed); !st) return st;
  if (r.contains("error")) return jc::member(r, where, "error", jc::string);
  if (auto st = jc::member(r, where, "metrics", check_metrics); !st) return st;
  if (auto st = jc::member(r, where, "undefined", jc::string_map, true); !st) return st;
  return jc::member(r, where, "warnings", jc::each_of(jc::string), true);
}

Status check_version(const Json& v, const std::string& where) {
  return jc::integer(v, where, 1, kMonteCarloPartVersion);
}

// The whole part against its schema (what part_to_json writes), before any value is read.
Status check_part(const Json& j, const std::string& where) {
  if (auto st = jc::object(j, where); !st) return st;
  if (auto st = jc::member(j, where, "version", check_version); !st) return st;
  for (const char* key : {"scenario", "shard"}) {
    if (auto st = jc::member(j, where, key, jc::string); !st) return st;
  }
  if (auto st = jc::member(j, where, "source", jc::string, true); !st) return st;
  if (j.at("version").get<double>() >= 2) {  // what makes parts parts of one run
    if (auto st = jc::member(j, where, "preset_hash", jc::string); !st) return st;
    const auto values = [](const Json& v, const std::string& w) { return jc::number_map(v, w); };
    if (auto st = jc::member(j, where, "values", values); !st) return st;
  }
  if (auto st = jc::member(j, where, "seeds", jc::each_of(check_seed)); !st) return st;
  if (auto st = jc::member(j, where, "t", jc::increasing_array); !st) return st;
  if (auto st = jc::member(j, where, "runs", jc::each_of(check_run)); !st) return st;
  const std::size_t runs = j.at("runs").size();
  const auto sums = [runs](const Json& v, const std::string& w) { return check_sums(v, w, runs); };
  if (auto n = j.find("nees"); n != j.end() && !n->is_null()) {
    if (auto st = sums(*n, jc::at(where, "nees")); !st) return st;
  }
  for (const char* key : {"error", "variance"}) {
    if (auto st = jc::member(j, where, key, sums, true); !st) return st;
  }
  if (auto st = jc::member(j, where, "error_unit", jc::string, true); !st) return st;
  return jc::member(j, where, "nis", jc::each_of(sums), true);
}

}  // namespace

Expected<MonteCarloPart> part_from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) return Error{where + ": a Monte Carlo part must be a JSON object"};
  const auto kind = j.find("kind");
  if (kind == j.end() || !kind->is_string() || *kind != kMonteCarloKind) {
    return Error{where + ": kind: expected \"" + std::string(kMonteCarloKind) + "\""};
  }
  if (auto st = check_part(j, where); !st) return st.err();
  MonteCarloPart p;
  try {
    p.version = j.at("version").get<int>();
    if (p.version >= 2) {
      p.preset_hash = j.at("preset_hash").get<std::string>();
      p.values = j.at("values").get<ParamValues>();
    }
    p.scenario = j.at("scenario").get<std::string>();
    p.source = j.value("source", std::string());
    p.seeds = j.at("seeds").get<std::vector<long long>>();
    auto shard = parse_shard(j.at("shard").get<std::string>(), "shard");
    if (!shard) return Error{where + ": " + shard.error()};
    p.shard = *shard;
    p.t = j.at("t").get<std::vector<double>>();
    for (const auto& r : j.at("runs")) {
      SeedRun run;
      run.seed = r.at("seed").get<long long>();
      if (r.contains("error")) {
        run.error = r.at("error").get<std::string>();
        if (run.error.empty())
          return Error{where + ": runs: seed " + std::to_string(run.seed) +
                       ": error: must not be empty"};
      } else {
        run.metrics = r.at("metrics").get<Metrics>();
        run.undefined = r.value("undefined", UndefinedMetrics{});
        run.warnings = r.value("warnings", std::vector<std::string>{});
      }
      p.runs.push_back(std::move(run));
    }
  } catch (const Json::exception& e) {
    return Error{where + ": " + e.what()};
  }
  if (auto n = j.find("nees"); n != j.end() && !n->is_null()) {
    auto s = sums_from_json(*n, where + ": nees");
    if (!s) return s.err();
    p.nees = std::move(*s);
  }
  if (j.contains("error") && j.contains("variance")) {
    auto e = sums_from_json(j["error"], where + ": error");
    if (!e) return e.err();
    auto v = sums_from_json(j["variance"], where + ": variance");
    if (!v) return v.err();
    p.error = std::move(*e);
    p.variance = std::move(*v);
    p.error_unit = j.value("error_unit", std::string());
  }
  if (auto n = j.find("nis"); n != j.end()) {
    if (!n->is_array()) return Error{where + ": nis: must be an array"};
    for (std::size_t i = 0; i < n->size(); ++i) {
      auto s = sums_from_json((*n)[i], where + ": nis[" + std::to_string(i) + "]");
      if (!s) return s.err();
      p.nis.push_back(std::move(*s));
    }
  }
  return p;
}

namespace {

// Parts of one run: the same preset content and values (version 2); a version-1 part records
// neither, so the check is impossible — said in `notes`.
template <class Name>
Status check_same_run(const std::vector<MonteCarloPart>& parts, const Name& name,
                      std::vector<std::string>* notes) {
  const MonteCarloPart* ref = nullptr;
  std::size_t ref_i = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const MonteCarloPart& p = parts[i];
    if (p.version < 2) {
      if (notes && parts.size() > 1) {
        notes->push_back(name(i) +
                         ": a version-1 part records no preset hash or values: "
                         "cannot check that it comes from the same run as the others");
      }
      continue;
    }
    if (!ref) {
      ref = &p;
      ref_i = i;
      continue;
    }
    if (p.preset_hash != ref->preset_hash) {
      return Error{name(i) + ": preset_hash: " + p.preset_hash + " differs from " + name(ref_i) +
                   "'s " + ref->preset_hash + " (the preset changed between the shards)"};
    }
    for (const auto& [k, v] : ref->values) {
      const auto it = p.values.find(k);
      if (it == p.values.end() || it->second != v) {
        std::ostringstream os;
        os << name(i) << ": values." << k << ": "
           << (it == p.values.end() ? std::string("missing") : fixed(it->second, 10))
           << " differs from " << name(ref_i) << "'s " << fixed(v, 10)
           << " (parts of different runs)";
        return Error{os.str()};
      }
    }
    for (const auto& [k, v] : p.values) {
      if (!ref->values.count(k))
        return Error{name(i) + ": values." + k + ": not in " + name(ref_i) +
                     " (parts of different runs)"};
    }
  }
  return Ok{};
}

// What a part's runs produced: NEES, error and variance, the NIS channels, e.g.
// "nees, error, variance, nis angle"; "" for a part without a completed run (nothing to compare).
std::string blocks_of(const MonteCarloPart& p) {
  if (std::none_of(p.runs.begin(), p.runs.end(), [](const SeedRun& r) { return r.error.empty(); }))
    return "";
  std::string b = p.nees ? "nees" : "no nees";
  b += p.error ? ", error" : "";
  b += p.variance ? ", variance" : "";
  b += p.nis.empty() ? ", no nis" : ", nis";
  for (const auto& s : p.nis)
    b += " " + quote_token(s.name);
  return b;
}

// Parts of one run hold the same blocks (a shard without a completed run holds none).
template <class Name>
Status check_same_blocks(const std::vector<MonteCarloPart>& parts, const Name& name) {
  std::size_t ref = parts.size();
  std::string ref_blocks;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string b = blocks_of(parts[i]);
    if (b.empty()) continue;
    if (ref == parts.size()) {
      ref = i;
      ref_blocks = b;
    } else if (b != ref_blocks) {
      return Error{name(i) + ": holds " + b + "; " + name(ref) + " holds " + ref_blocks +
                   " (parts of different runs)"};
    }
  }
  return Ok{};
}

}  // namespace

Expected<MonteCarloPart> merge_montecarlo_parts(const std::vector<MonteCarloPart>& parts,
                                                const std::vector<std::string>& names,
                                                std::vector<std::string>* notes) {
  auto name = [&](std::size_t i) {
    return i < names.size() ? names[i] : "part " + std::to_string(i + 1);
  };
  if (parts.empty()) return Error{"merge: no parts"};
  const MonteCarloPart& first = parts.front();
  if (auto st = check_same_run(parts, name, notes); !st) return st.err();
  if (auto st = check_same_blocks(parts, name); !st) return st.err();
  MonteCarloPart out;
  out.version = first.version;
  out.preset_hash = first.preset_hash;
  out.values = first.values;
  for (const auto& p : parts)
    out.version = std::min(out.version, p.version);
  if (out.version < 2) {
    out.preset_hash.clear();
    out.values.clear();
  }
  out.scenario = first.scenario;
  out.source = first.source;
  out.seeds = first.seeds;
  out.shard = Shard{1, 1};
  std::set<std::size_t> shards;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const MonteCarloPart& p = parts[i];
    if (p.scenario != first.scenario) {
      return Error{name(i) + ": scenario '" + p.scenario + "' differs from " + name(0) + "'s '" +
                   first.scenario + "'"};
    }
    if (p.seeds != first.seeds)
      return Error{name(i) + ": its seed set differs from " + name(0) + "'s"};
    if (p.shard.count != first.shard.count) {
      return Error{name(i) + ": shard " + shard_text(p.shard) + " is not one of " +
                   std::to_string(first.shard.count) + " shards (" + name(0) + ": " +
                   shard_text(first.shard) + ")"};
    }
    if (!shards.insert(p.shard.index).second) {
      return Error{name(i) + ": shard " + shard_text(p.shard) + " is given twice"};
    }
    for (const auto& r : p.runs)
      out.runs.push_back(r);
    if (p.t.size() > out.t.size()) out.t = p.t;
    if (p.nees) {
      if (!out.nees) {
        out.nees = *p.nees;
      } else if (auto st = out.nees->merge(*p.nees); !st) {
        return Error{name(i) + ": nees: " + st.error()};
      }
    }
    for (auto [mine, theirs, key] : {std::tuple{&out.error, &p.error, "error"},
                                     std::tuple{&out.variance, &p.variance, "variance"}}) {
      if (!*theirs) continue;
      if (!*mine) {
        *mine = **theirs;
        out.error_unit = p.error_unit;
      } else if (auto st = (*mine)->merge(**theirs); !st) {
        return Error{name(i) + ": " + key + ": " + st.error()};
      }
    }
    for (const auto& s : p.nis) {
      auto it = std::find_if(out.nis.begin(), out.nis.end(),
                             [&](const StepSums& o) { return o.name == s.name; });
      if (it == out.nis.end()) {
        out.nis.push_back(s);
      } else if (auto st = it->merge(s); !st) {
        return Error{name(i) + ": nis: " + st.error()};
      }
    }
  }
  for (std::size_t k = 1; k <= first.shard.count; ++k) {
    if (!shards.count(k)) {
      return Error{"merge: shard " + std::to_string(k) + "/" + std::to_string(first.shard.count) +
                   " is missing"};
    }
  }
  std::sort(out.runs.begin(), out.runs.end(),
            [](const SeedRun& a, const SeedRun& b) { return a.seed < b.seed; });
  for (std::size_t i = 1; i < out.runs.size(); ++i) {
    if (out.runs[i].seed == out.runs[i - 1].seed) {
      return Error{"merge: seed " + std::to_string(out.runs[i].seed) + " is in two parts"};
    }
  }
  if (out.runs.size() != out.seeds.size()) {
    std::string which;
    for (std::size_t i = 0; i < parts.size(); ++i)
      which += (i ? ", " : "") + name(i);
    return Error{"merge: " + which + (parts.size() == 1 ? " holds " : " hold ") +
                 std::to_string(out.runs.size()) + " runs of a set of " +
                 std::to_string(out.seeds.size()) + " seeds"};
  }
  return out;
}

nlohmann::ordered_json summary_to_json(const MonteCarloSummary& s, bool steps) {
  OJson j;
  j["scenario"] = s.scenario;
  j["seeds"] = s.seeds;
  j["completed"] = s.completed;
  OJson stopped = OJson::array();
  for (const auto& r : s.stopped)
    stopped.push_back({{"seed", r.seed}, {"error", r.error}});
  j["stopped"] = std::move(stopped);
  OJson metrics = OJson::object();
  for (const auto& [k, m] : s.metrics) {
    metrics[k] = {{"n", m.n}, {"mean", m.mean}, {"sd", m.sd}, {"min", m.min}, {"max", m.max}};
  }
  j["metrics"] = std::move(metrics);
  j["undefined"] = s.undefined;
  OJson cons = OJson::object();
  if (s.nees) cons["anees"] = consistency_json(*s.nees);
  for (const auto& c : s.nis)
    cons["anis." + c.name] = consistency_json(c);
  j["consistency"] = std::move(cons);
  if (steps) {
    // Per-step arrays; null where no run has a value at that step.
    OJson st;
    st["t"] = s.t;
    if (s.nees) {
      st["anees"] = s.nees->average;
      st["anees_lo"] = s.nees->lo_k;
      st["anees_hi"] = s.nees->hi_k;
    }
    for (const auto& c : s.nis) {
      st["anis." + c.name] = c.average;
      st["anis." + c.name + "_lo"] = c.lo_k;
      st["anis." + c.name + "_hi"] = c.hi_k;
    }
    if (s.error) {
      st["error_mean." + s.error->state] = s.error->mean;
      st["error_sd." + s.error->state] = s.error->sd;
      st["filter_sigma." + s.error->state] = s.error->filter_sigma;
    }
    j["steps"] = std::move(st);
  }
  return j;
}

std::string summary_table(const MonteCarloSummary& s) {
  std::ostringstream os;
  os << s.scenario << ": " << s.seeds << " seeds, " << s.completed << " completed";
  if (!s.stopped.empty()) {
    os << ", " << s.stopped.size() << " stopped (seeds";
    for (const auto& r : s.stopped)
      os << " " << r.seed;
    os << ")";
  }
  os << "\n\n";
  std::size_t width = 6;
  for (const auto& [k, m] : s.metrics)
    width = std::max(width, k.size());
  os << std::left << std::setw(static_cast<int>(width) + 2) << "metric" << std::right
     << std::setw(5) << "n" << std::setw(14) << "mean" << std::setw(14) << "sd" << std::setw(14)
     << "min" << std::setw(14) << "max"
     << "\n";
  for (const auto& [k, m] : s.metrics) {
    os << std::left << std::setw(static_cast<int>(width) + 2) << k << std::right << std::setw(5)
       << m.n << std::setw(14) << fixed(m.mean) << std::setw(14) << fixed(m.sd) << std::setw(14)
       << fixed(m.min) << std::setw(14) << fixed(m.max) << "\n";
  }
  for (const auto& [k, why] : s.undefined)
    os << std::left << std::setw(static_cast<int>(width) + 2) << k << "undefined: " << why << "\n";
  auto line = [&](const std::string& what, const ConsistencySummary& c) {
    os << what << " (" << fixed(c.dof, 3) << " dof, " << c.runs << " runs): time average "
       << fixed(c.time_average, 4) << ", 95 % bounds [" << fixed(c.lo, 4) << ", " << fixed(c.hi, 4)
       << "], " << fixed(100.0 * c.inside, 3) << " % of steps inside\n";
  };
  if (s.nees || !s.nis.empty()) os << "\n";
  if (s.nees) line("ANEES", *s.nees);
  for (const auto& c : s.nis)
    line("ANIS " + c.label, c);
  return os.str();
}

}  // namespace kfw
