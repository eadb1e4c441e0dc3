// merge --resume DIR: which parts of a Slurm array's output folder are missing or invalid, and
// the array indices to resubmit (docs/cluster.md). Only complete, schema-valid parts are trusted:
// a part is valid when it parses, passes its kind's schema check (the checks merge makes) and
// holds the shard its file name says (part_<i>.json holds shard i/N).
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_commands.h"
#include "core/suggest.h"
#include "data/json_io.h"
#include "experiment/monte_carlo.h"
#include "experiment/sweep_part.h"
#include "experiment/tune_part.h"

namespace kfw {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// What ties the parts of one job together, and the part's shard.
struct PartIdentity {
  std::string kind;
  Json same;  // kind, preset hash, values: equal in every part of one job
  Shard shard;
};

Expected<PartIdentity> identify(const Json& doc, const std::string& path) {
  if (!doc.is_object() || !doc.contains("kind") || !doc.at("kind").is_string()) {
    return Error{path + ": kind: missing"};
  }
  PartIdentity id;
  id.kind = doc.at("kind").get<std::string>();
  id.same["kind"] = id.kind;
  if (id.kind == kMonteCarloKind) {
    auto p = part_from_json(doc, path);
    if (!p) return p.err();
    id.shard = p->shard;
    id.same["values"] = doc.value("values", Json::object());
    id.same["seeds"] = doc.at("seeds");
  } else if (id.kind == "sweep") {
    if (auto st = check_sweep_part(doc, path); !st) return st.err();
    id.shard = {doc.at("shard").at("index").get<std::size_t>(),
                doc.at("shard").at("count").get<std::size_t>()};
    for (const char* key : {"base", "axes", "metric"})
      id.same[key] = doc.at(key);
  } else if (id.kind == kTunePartKind) {
    if (auto st = check_tune_part(doc, path); !st) return st.err();
    id.shard = *parse_shard(doc.at("shard").get<std::string>(), "shard");
    id.same["values"] = doc.at("values");
    id.same["objective"] = doc.at("objective");
  } else {
    return Error{path + ": kind: unknown '" + id.kind + "'"};
  }
  id.same["preset_hash"] = doc.value("preset_hash", std::string());
  id.same["count"] = id.shard.count;
  return id;
}

// "1-3,7": the indices as a Slurm array specification.
std::string array_spec(const std::vector<std::size_t>& idx) {
  std::string s;
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && idx[j + 1] == idx[j] + 1)
      ++j;
    s += (s.empty() ? "" : ",") + std::to_string(idx[i]);
    if (j > i) s += "-" + std::to_string(idx[j]);
    i = j + 1;
  }
  return s;
}

}  // namespace

int cmd_merge_resume(const std::string& dir, std::ostream& out, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return fail(err, Error{"--resume: " + dir + ": not a directory"});
  const std::regex name("part_([0-9]{1,9})\\.json");
  std::map<std::size_t, std::string> problems;  // index → why
  std::map<std::size_t, PartIdentity> valid;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::smatch m;
    const std::string file = it->path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const std::size_t index = std::stoul(m[1]);
    const std::string path = it->path().string();
    auto doc = read_json_document(path, "part");
    auto id = doc ? identify(*doc, path) : Expected<PartIdentity>(doc.err());
    if (!id) {
      problems[index] = one_line(id.error());
    } else if (id->shard.index != index) {
      problems[index] = path + ": holds shard " + std::to_string(id->shard.index) + "/" +
                        std::to_string(id->shard.count) + ", not " + std::to_string(index);
    } else {
      valid.emplace(index, std::move(*id));
    }
  }
  if (valid.empty()) {
    for (const auto& [i, why] : problems)
      err << "kfw-cli: part_" << i << ".json: invalid: " << why << "\n";
    return fail(err, Error{"--resume: " + dir +
                           ": no complete part (part_<i>.json) to take the shard count from; "
                           "submit the whole array again"});
  }
  const PartIdentity& first = valid.begin()->second;
  for (const auto& [i, id] : valid) {
    if (id.same != first.same) {
      return fail(err, Error{"--resume: " + dir + ": part_" + std::to_string(i) +
                             ".json and part_" + std::to_string(valid.begin()->first) +
                             ".json are parts of different jobs (preset, values or grid differ)"});
    }
  }
  const std::size_t count = first.shard.count;
  std::vector<std::size_t> redo;
  for (std::size_t i = 1; i <= count; ++i) {
    if (valid.count(i)) continue;
    redo.push_back(i);
    const auto p = problems.find(i);
    err << "kfw-cli: part_" << i
        << ".json: " << (p == problems.end() ? std::string("missing") : "invalid: " + p->second)
        << "\n";
  }
  for (const auto& [i, why] : problems) {
    if (i > count)
      err << "kfw-cli: warning: part_" << i << ".json is not one of the " << count
          << " shards: " << why << "\n";
  }
  err << "kfw-cli: " << first.kind << ": " << count - redo.size() << " of " << count
      << " parts complete" << (redo.empty() ? "; merge them" : "; resubmit the indices printed")
      << "\n";
  out << array_spec(redo) << "\n";
  return kExitOk;
}

}  // namespace kfw
