#include "document/session.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/suggest.h"
#include "data/csv.h"
#include "data/input_file.h"
#include "data/json_io.h"
#include "document/file_paths.h"

namespace kfw {

using nlohmann::json;

namespace {

json values_json(const ParamValues& v) {
  json j = json::object();
  for (const auto& [k, x] : v)
    j[k] = x;
  return j;
}

Expected<ParamValues> values_from(const json& j, const std::string& where) {
  if (!j.is_object()) return Error{where + ": must be an object of numbers"};
  ParamValues v;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it->is_number())
      return Error{where + "." + truncate_token(it.key()) + ": must be a number"};
    v[it.key()] = it->get<double>();
  }
  return v;
}

}  // namespace

std::string session_to_json(const Session& s) {
  nlohmann::ordered_json j;
  j["format"] = kSessionFormat;
  j["version"] = kSessionVersion;
  j["preset"] = s.preset_path;
  j["scenario"] = s.scenario;
  j["values"] = values_json(s.values);
  if (s.data_path) {
    j["data"] = {{"path", *s.data_path}, {"fnv1a64", s.data_hash}};
  } else {
    j["data"] = nullptr;
  }
  j["mapping"] = mapping_to_json(s.mapping);
  j["tuning_set"] = nlohmann::ordered_json::array();
  for (const auto& d : s.tuning_set)
    j["tuning_set"].push_back({{"path", d.path}, {"mapping", mapping_to_json(d.mapping)}});
  j["snapshots"] = nlohmann::ordered_json::array();
  for (const auto& snap : s.snapshots) {
    j["snapshots"].push_back({{"name", snap.name}, {"values", values_json(snap.values)}});
  }
  j["window"] = s.window_state;
  return j.dump(2) + "\n";
}

namespace {

// The keys of each object of a session: version 3 as written; versions 1 and 2 also "columns"
// (version 1's name for the mapping).
const std::vector<std::string> kSessionKeys = {"format",    "version", "preset",  "scenario",
                                               "values",    "data",    "mapping", "tuning_set",
                                               "snapshots", "window"};
const std::vector<std::string> kDataKeys = {"path", "fnv1a64"};
const std::vector<std::string> kTuningKeys = {"path", "mapping"};
const std::vector<std::string> kSnapshotKeys = {"name", "values"};

// Keys of `obj` (at dotted `where`, "" for the top) not among `keys`: refused in version 3, a
// notice naming the key and `kfw-cli upgrade` in versions 1 and 2.
Status check_keys(const json& obj, const std::vector<std::string>& keys, const std::string& where,
                  const std::string& path, Session& s) {
  if (!obj.is_object()) return Ok{};
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (std::find(keys.begin(), keys.end(), it.key()) != keys.end()) continue;
    if (where.empty() && it.key() == "columns" && s.version < 3) continue;
    const std::string at = where.empty() ? truncate_token(it.key()) : key_path(where, it.key());
    if (s.version >= 3) {
      return Error{path + ": " + at + ": " + unknown_message("key", it.key(), keys)};
    }
    s.notices.push_back(path + ": " + at + ": unknown key in a version-" +
                        std::to_string(s.version) + " session, ignored; kfw-cli upgrade " + path +
                        " rewrites it in the current form");
  }
  return Ok{};
}

// The version: 1, 2 or 3; a higher one was written by a newer kfw.
Expected<int> session_version(const json& j, const std::string& path) {
  auto v = j.find("version");
  if (v == j.end() || !v->is_number_integer()) {
    return Error{path + ": version: must be a whole number (1, 2 or 3)"};
  }
  if (v->is_number_unsigned() && v->get<std::uint64_t>() > kSessionVersion) {
    return Error{path + ": version: " + v->dump() + ": written by a newer kfw (version " +
                 v->dump() + "); this build reads versions 1 to " +
                 std::to_string(kSessionVersion)};
  }
  const std::int64_t n = v->get<std::int64_t>();
  if (n < 1 || n > kSessionVersion) return Error{path + ": version: must be 1, 2 or 3"};
  return static_cast<int>(n);
}

Status check_all_keys(const json& j, const std::string& path, Session& s) {
  if (auto st = check_keys(j, kSessionKeys, "", path, s); !st) return st;
  if (auto d = j.find("data"); d != j.end()) {
    if (auto st = check_keys(*d, kDataKeys, "data", path, s); !st) return st;
  }
  for (const char* list : {"tuning_set", "snapshots"}) {
    auto l = j.find(list);
    if (l == j.end() || !l->is_array()) continue;
    const auto& keys = std::string_view(list) == "tuning_set" ? kTuningKeys : kSnapshotKeys;
    for (std::size_t i = 0; i < l->size(); ++i) {
      if (auto st = check_keys((*l)[i], keys, index_path(list, i), path, s); !st) return st;
    }
  }
  return Ok{};
}

Expected<Session> session_from_json(const json& j, const std::string& path) {
  if (!j.is_object()) return Error{path + ": a session must be a JSON object"};
  if (!j.contains("format") || j["format"] != kSessionFormat) {
    return Error{path + ": format: must be '" + std::string(kSessionFormat) + "'"};
  }
  auto version = session_version(j, path);
  if (!version) return version.err();
  Session s;
  s.version = *version;
  if (auto st = check_all_keys(j, path, s); !st) return st.err();
  for (const char* key : {"preset", "scenario"}) {
    if (!j.contains(key) || !j[key].is_string())
      return Error{path + ": key '" + key + "' must be a string"};
  }
  s.preset_path = j["preset"].get<std::string>();
  s.scenario = j["scenario"].get<std::string>();
  auto v = values_from(j.value("values", json::object()), path + ": values");
  if (!v) return v.err();
  s.values = *v;
  if (j.contains("data") && !j["data"].is_null()) {
    const json& d = j["data"];
    if (!d.is_object() || !d.contains("path") || !d["path"].is_string()) {
      return Error{path + ": key 'data' must hold a string 'path'"};
    }
    s.data_path = d["path"].get<std::string>();
    if (d.contains("fnv1a64") && d["fnv1a64"].is_string())
      s.data_hash = d["fnv1a64"].get<std::string>();
  }
  for (const char* key : {"columns", "mapping"}) {  // version 1 wrote "columns"
    if (!j.contains(key)) continue;
    auto m = mapping_from_json(j[key], key);
    if (!m) return Error{path + ": " + m.error()};
    s.mapping.override_with(*m);
  }
  if (j.contains("tuning_set")) {
    if (!j["tuning_set"].is_array()) return Error{path + ": tuning_set: must be an array"};
    for (std::size_t i = 0; i < j["tuning_set"].size(); ++i) {
      const json& e = j["tuning_set"][i];
      const std::string at = index_path("tuning_set", i);
      if (!e.is_object() || !e.contains("path") || !e["path"].is_string()) {
        return Error{path + ": " + at + ": needs a string 'path'"};
      }
      DataRef d{e["path"].get<std::string>(), {}};
      if (e.contains("mapping")) {
        auto m = mapping_from_json(e["mapping"], key_path(at, "mapping"));
        if (!m) return Error{path + ": " + m.error()};
        d.mapping = *m;
      }
      s.tuning_set.push_back(std::move(d));
    }
  }
  if (j.contains("snapshots")) {
    if (!j["snapshots"].is_array()) return Error{path + ": key 'snapshots' must be an array"};
    for (const auto& e : j["snapshots"]) {
      if (!e.is_object() || !e.contains("name") || !e["name"].is_string()) {
        return Error{path + ": every snapshot needs a string 'name'"};
      }
      auto sv = values_from(e.value("values", json::object()),
                            path + ": snapshots." + e["name"].get<std::string>());
      if (!sv) return sv.err();
      s.snapshots.push_back({e["name"].get<std::string>(), *sv});
    }
  }
  if (j.contains("window") && j["window"].is_string())
    s.window_state = j["window"].get<std::string>();
  return s;
}

}  // namespace

Expected<Session> parse_session(const std::string& text, const std::string& path) {
  auto doc = parse_json_document(text, path);
  if (!doc) return doc.err();
  return session_from_json(*doc, path);
}

Expected<Session> load_session(const std::string& path) {
  auto doc = read_json_document(path, "session");
  if (!doc) return doc.err();
  auto s = session_from_json(*doc, path);
  if (!s) return s;
  // Paths are the session file's (a session written before that: the current folder's).
  s->preset_path = path_from_file(s->preset_path, path, true);
  if (s->data_path) s->data_path = path_from_file(*s->data_path, path, true);
  for (auto& d : s->tuning_set)
    d.path = path_from_file(d.path, path, true);
  return s;
}

Status save_session(const std::string& path, const Session& s) {
  // Paths relative to where the session is written, so a copied or moved folder still opens.
  Session out = s;
  std::error_code ec;  // a preset named by its name (no file) stays a name
  if (std::filesystem::exists(s.preset_path, ec))
    out.preset_path = path_for_file(s.preset_path, path);
  if (s.data_path) out.data_path = path_for_file(*s.data_path, path);
  for (auto& d : out.tuning_set)
    d.path = path_for_file(d.path, path);
  return write_text_file_atomic(path, session_to_json(out));
}

namespace {

constexpr std::uint64_t kFnvOffset = 1469598103934665603ull, kFnvPrime = 1099511628211ull;

void fnv_add(std::uint64_t& h, const char* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(p[i]);
    h *= kFnvPrime;
  }
}

std::string hex(std::uint64_t h) {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

}  // namespace

Expected<std::string> file_hash(const std::string& path) {
  auto fd = open_input_file(path, limits::Input::kData);
  if (!fd) return fd.err();
  std::uint64_t h = kFnvOffset;
  char buf[65536];
  ssize_t n = 0;
  while ((n = ::read(*fd, buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR)) {
    if (n > 0) fnv_add(h, buf, static_cast<std::size_t>(n));
  }
  ::close(*fd);
  if (n < 0) return Error{path + ": read error"};
  return hex(h);
}

std::string text_hash(std::string_view text) {
  std::uint64_t h = kFnvOffset;
  fnv_add(h, text.data(), text.size());
  return hex(h);
}

Expected<Dataset> apply_column_map(Dataset d, const ColumnMap& map) {
  for (const auto& [role, column] : map) {
    if (column.empty()) continue;
    const int i = d.index(column);
    if (i < 0)
      return Error{d.source + ": mapped column '" + column + "' (for '" + role +
                   "') is not in the file"};
    if (role == column) continue;
    if (const int clash = d.index(role); clash >= 0)
      d.names[static_cast<std::size_t>(clash)] += ".unmapped";
    d.names[static_cast<std::size_t>(i)] = role;
  }
  return d;
}

Mapping to_mapping(const ColumnMap& map) {
  Mapping m;
  for (const auto& [role, column] : map) {
    if (!column.empty()) m[role].column = column;
  }
  return m;
}

std::string header_key(const Dataset& d) {
  std::string k;
  for (const auto& n : d.names)
    k += (k.empty() ? "" : ",") + n;
  return k;
}

}  // namespace kfw
