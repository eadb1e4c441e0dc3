// Sessions: everything a user set up (preset, values, dataset path and hash, column mapping,
// snapshots, window layout) in one JSON file, written atomically.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/param_spec.h"
#include "data/mapping.h"

namespace kfw {

inline constexpr const char* kSessionFormat = "kfw-session";
inline constexpr int kSessionVersion = 3;  // written; 1, 2 and 3 are read

// A pinned tuning, compared against the live one.
struct Snapshot {
  std::string name;
  ParamValues values;
  bool operator==(const Snapshot&) const = default;
};

// role (the scenario's column name) -> the file's column name
using ColumnMap = std::map<std::string, std::string>;

struct Session {
  int version = kSessionVersion;  // the version the file declared
  std::string preset_path;
  std::string scenario;
  ParamValues values;
  std::optional<std::string> data_path;
  std::string data_hash;  // FNV-1a 64 of the file's bytes, hex; empty for simulated data
  Mapping mapping;        // how the dataset's columns become roles (version 1: "columns")
  std::vector<DataRef> tuning_set;
  std::vector<Snapshot> snapshots;
  std::string window_state;  // opaque to the engine (the GUI's base64 geometry/state)
  // Keys a session of version 1 or 2 holds that this build does not know (ignored; version 3
  // refuses them), one line each naming the key and `kfw-cli upgrade`.
  std::vector<std::string> notices;
};

std::string session_to_json(const Session& s);
Expected<Session> parse_session(const std::string& text, const std::string& path);
Expected<Session> load_session(const std::string& path);
Status save_session(const std::string& path, const Session& s);

// FNV-1a 64-bit hash of a file's bytes, as 16 hex digits.
Expected<std::string> file_hash(const std::string& path);
// The same hash of bytes in memory (a preset without a file).
std::string text_hash(std::string_view text);

// Renames the mapped file columns to their roles. Errors name a mapped column the file lacks.
Expected<Dataset> apply_column_map(Dataset d, const ColumnMap& map);
// A plain role -> column map as a mapping (no unit, scale or offset).
Mapping to_mapping(const ColumnMap& map);
// The header as one string ("t,gx,acc_roll,..."): the key a mapping is remembered under.
std::string header_key(const Dataset& d);

}  // namespace kfw
