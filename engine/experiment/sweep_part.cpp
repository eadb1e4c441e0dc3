#include "experiment/sweep_part.h"

#include <cmath>
#include <map>
#include <set>

#include "data/json_check.h"
#include "experiment/grammar.h"
#include "experiment/sweep.h"

namespace kfw {

namespace {

namespace jc = json_check;
using Doc = nlohmann::json;

Status check_axis(const Doc& a, const std::string& where) {
  if (auto st = jc::object(a, where); !st) return st;
  if (auto st = jc::member(a, where, "key", jc::string); !st) return st;
  for (const char* k : {"lo", "hi"}) {
    if (auto st = jc::member(a, where, k,
                             [](const Doc& v, const std::string& w) { return jc::finite(v, w); });
        !st)
      return st;
  }
  if (auto st = jc::member(a, where, "n",
                           [](const Doc& v, const std::string& w) {
                             return jc::integer(v, w, 1, static_cast<double>(kMaxGridPoints));
                           });
      !st)
    return st;
  if (auto st = jc::member(a, where, "log", jc::boolean); !st) return st;
  if (a.at("log").get<bool>() && !(a.at("lo").get<double>() > 0 && a.at("hi").get<double>() > 0))
    return Error{where + ": a log axis needs lo and hi above 0"};
  return Ok{};
}

// The axes' grid values (the part's axes are checked), and the grid's size (or an error).
Expected<std::vector<std::vector<double>>> grid_values(const Doc& axes, const std::string& where,
                                                       double total) {
  std::vector<SweepAxis> parsed;
  std::vector<std::vector<double>> values;
  for (const auto& a : axes) {
    SweepAxis ax{a.at("key").get<std::string>(), a.at("lo").get<double>(), a.at("hi").get<double>(),
                 a.at("n").get<int>(), a.at("log").get<bool>()};
    values.push_back(ax.values());
    parsed.push_back(std::move(ax));
  }
  const auto size = grid_size(parsed, kMaxGridPoints);
  if (!size || static_cast<double>(*size) != total) {
    return Error{jc::at(where, "total_points") + ": " + Doc(total).dump() +
                 " is not the size of the grid of \"axes\"" +
                 (size ? " (" + std::to_string(*size) + ")" : std::string(" (too large)"))};
  }
  return values;
}

// A coordinate as written (the grid value, rounded for an integer parameter), to rounding.
bool on_grid(double at, double v) {
  const auto near = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(b), 1.0);
  };
  return near(at, v) || near(at, std::round(v));
}

Status check_header(const Doc& j, const std::string& where) {
  if (auto st = jc::object(j, where); !st) return st;
  if (auto st = jc::member(j, where, "version",
                           [](const Doc& v, const std::string& w) {
                             return jc::integer(v, w, 1, kSweepPartVersion);
                           });
      !st)
    return st;
  for (const char* k : {"scenario", "metric", "direction"}) {
    if (auto st = jc::member(j, where, k, jc::string); !st) return st;
  }
  if (j.at("version").get<double>() >= 2) {
    if (auto st = jc::member(j, where, "preset_hash", jc::string); !st) return st;
  }
  const auto finite = [](const Doc& v, const std::string& w) { return jc::finite(v, w); };
  if (auto st = jc::member(j, where, "target", finite, true); !st) return st;
  if (auto st = jc::member(j, where, "axes", jc::each_of(check_axis)); !st) return st;
  const auto base = [](const Doc& v, const std::string& w) { return jc::number_map(v, w); };
  if (auto st = jc::member(j, where, "base", base); !st) return st;
  const auto positive = [](const Doc& v, const std::string& w) { return jc::integer(v, w, 1); };
  if (auto st = jc::member(j, where, "shard",
                           [&](const Doc& v, const std::string& w) -> Status {
                             if (auto st2 = jc::object(v, w); !st2) return st2;
                             if (auto st2 = jc::member(v, w, "index", positive); !st2) return st2;
                             if (auto st2 = jc::member(v, w, "count", positive); !st2) return st2;
                             if (v.at("index").get<double>() > v.at("count").get<double>())
                               return Error{jc::at(w, "index") + ": more than the shard count"};
                             return Ok{};
                           });
      !st)
    return st;
  const auto points = [](const Doc& v, const std::string& w) {
    return jc::integer(v, w, 1, static_cast<double>(kMaxGridPoints));
  };
  return jc::member(j, where, "total_points", points);
}

}  // namespace

Status check_sweep_part(const Doc& j, const std::string& where) {
  if (auto st = check_header(j, where); !st) return st;
  const double total = j.at("total_points").get<double>();
  auto values = grid_values(j.at("axes"), where, total);
  if (!values) return values.err();
  const auto shard_index = j.at("shard").at("index").get<std::size_t>();
  const auto shard_count = j.at("shard").at("count").get<std::size_t>();
  const std::size_t dims = values->size();
  std::set<std::size_t> seen;
  const auto point = [&](const Doc& p, const std::string& w) -> Status {
    if (auto st2 = jc::object(p, w); !st2) return st2;
    if (auto st2 = jc::member(
            p, w, "index",
            [&](const Doc& v, const std::string& w2) { return jc::integer(v, w2, 0, total - 1); });
        !st2)
      return st2;
    const auto index = p.at("index").get<std::size_t>();
    if (index % shard_count != shard_index - 1) {
      return Error{jc::at(w, "index") + ": point " + std::to_string(index) + " is not in shard " +
                   std::to_string(shard_index) + "/" + std::to_string(shard_count)};
    }
    if (!seen.insert(index).second)
      return Error{jc::at(w, "index") + ": point " + std::to_string(index) + " given twice"};
    if (auto st2 =
            jc::member(p, w, "at",
                       [](const Doc& v, const std::string& w2) { return jc::finite_array(v, w2); });
        !st2)
      return st2;
    const Doc& at = p.at("at");
    if (at.size() != dims) {
      return Error{jc::at(w, "at") + ": " + std::to_string(at.size()) + " coordinates for " +
                   std::to_string(dims) + " axes"};
    }
    const std::vector<double> expect = grid_point(*values, index);
    for (std::size_t a = 0; a < dims; ++a) {
      if (!on_grid(at[a].get<double>(), expect[a])) {
        return Error{jc::at(w, "at") + "[" + std::to_string(a) + "]: " + at[a].dump() +
                     " is not point " + std::to_string(index) + "'s coordinate on the grid (" +
                     Doc(expect[a]).dump() + ")"};
      }
    }
    if (p.contains("error")) return jc::member(p, w, "error", jc::string);
    const auto value = [](const Doc& v, const std::string& w2) -> Status {
      return v.is_null() ? Status(Ok{}) : jc::finite(v, w2);
    };
    return jc::member(p, w, "value", value, true);
  };
  if (auto st = jc::member(j, where, "points", jc::each_of(point)); !st) return st;
  const std::size_t held = j.at("points").size();
  const std::size_t due =
      shard_size(static_cast<std::size_t>(total), Shard{shard_index, shard_count});
  if (held != due) {
    return Error{jc::at(where, "points") + ": " + std::to_string(held) + " points; shard " +
                 std::to_string(shard_index) + "/" + std::to_string(shard_count) + " of a " +
                 std::to_string(static_cast<std::size_t>(total)) + "-point grid holds " +
                 std::to_string(due)};
  }
  return Ok{};
}

Expected<Doc> merge_sweep_documents(const std::vector<Doc>& parts,
                                    const std::vector<std::string>& paths) {
  if (parts.empty()) return Error{"merge: no parts"};
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (auto st = check_sweep_part(parts[i], paths[i]); !st) return st.err();
  }
  const Doc& first = parts.front();
  const auto count = first.at("shard").at("count").get<std::size_t>();
  std::vector<int> seen(count + 1, 0);
  std::map<std::size_t, Doc> points;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const Doc& p = parts[i];
    for (const char* key :
         {"version", "scenario", "metric", "direction", "axes", "base", "total_points"}) {
      if (p.at(key) != first.at(key)) {
        return Error{paths[i] + ": " + key + ": differs from " + paths.front() +
                     " (parts of different sweeps)"};
      }
    }
    if (p.contains("target") != first.contains("target") ||
        (first.contains("target") && p.at("target") != first.at("target")))
      return Error{paths[i] + ": target: differs from " + paths.front()};
    if (p.contains("preset_hash") && p.at("preset_hash") != first.at("preset_hash")) {
      return Error{paths[i] + ": preset_hash: differs from " + paths.front() +
                   " (the preset changed between the shards)"};
    }
    if (p.at("shard").at("count") != first.at("shard").at("count")) {
      return Error{paths[i] + ": shard: split into a different number of shards"};
    }
    const auto index = p.at("shard").at("index").get<std::size_t>();
    if (seen[index]++) {
      return Error{paths[i] + ": shard " + std::to_string(index) + "/" + std::to_string(count) +
                   " given twice"};
    }
    for (const auto& pt : p.at("points"))
      points[pt.at("index").get<std::size_t>()] = pt;
  }
  for (std::size_t k = 1; k <= count; ++k) {
    if (!seen[k]) {
      return Error{"merge: shard " + std::to_string(k) + "/" + std::to_string(count) +
                   " is missing"};
    }
  }
  Doc doc = first;
  doc["shard"] = {{"index", 1}, {"count", 1}};
  doc["points"] = Doc::array();
  for (auto& [index, pt] : points)
    doc["points"].push_back(std::move(pt));
  if (doc.at("points").size() != first.at("total_points").get<std::size_t>()) {
    return Error{"merge: the parts hold " + std::to_string(doc.at("points").size()) + " of " +
                 first.at("total_points").dump() + " points"};
  }
  return doc;
}

}  // namespace kfw
