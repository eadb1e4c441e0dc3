#include "document/import_args.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/suggest.h"
#include "data/import.h"
#include "data/json_io.h"
#include "document/workspace.h"

namespace kfw {

namespace {

struct KeyValue {
  std::string key, value;
};

Expected<KeyValue> split_kv(const std::string& opt, const std::string& text, const char* form) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    return Error{opt + ": expected " + form + ", got " + quote_token(text)};
  }
  return KeyValue{text.substr(0, eq), text.substr(eq + 1)};
}

Expected<double> number(const std::string& opt, const KeyValue& kv) {
  double v = 0.0;
  const char* b = kv.value.data();
  const char* e = b + kv.value.size();
  auto r = fast_float::from_chars(b + (*b == '+' ? 1 : 0), e, v);
  if (r.ec != std::errc() || r.ptr != e || !std::isfinite(v)) {
    return Error{opt + " " + kv.key + "=" + kv.value + ": " + quote_token(kv.value) +
                 " is not a finite number"};
  }
  return v;
}

bool is_time_unit(const std::string& u) {
  return is_iso_unit(u) || u == "s" || u == "ms" || u == "us" || u == "ns";
}

// "iso@ZONE" names a zone of the system's database.
Status check_iso_zone(const std::string& option, const std::string& unit) {
  if (const std::string zone = iso_zone(unit); !zone.empty()) {
    if (auto st = check_time_zone(zone); !st) return Error{option + ": " + st.error()};
  }
  return Ok{};
}

// --sep and --header: the file's format, over the mapping's.
Status apply_format_args(const ImportArgs& imp, Mapping& m) {
  if (imp.sep) {
    auto s = parse_separator(*imp.sep);
    if (!s) return Error{"--sep: " + s.error()};
    m.separator = *s;
  }
  if (imp.header) {
    auto h = parse_header_row(*imp.header);
    if (!h) return Error{"--header: " + h.error()};
    m.header = *h;
  }
  return Ok{};
}

// --mapping FILE: the preset's "mapping" block, alone or inside {"mapping": ...}.
// A mapping file (or a preset's "mapping" block in one): each role it names must be one of
// `roles` (a misspelt role was reported as "column mapped to both").
Status apply_mapping_file(const std::string& path, const std::vector<std::string>& roles,
                          Mapping& m) {
  auto j = read_json_document(path, "mapping");
  if (!j) return j.err();
  const nlohmann::json& block = j->is_object() && j->contains("mapping") ? (*j)["mapping"] : *j;
  auto file = mapping_from_json(block, path + ": mapping");
  if (!file) return file.err();
  for (const auto& [role, r] : *file) {
    if (std::find(roles.begin(), roles.end(), role) == roles.end()) {
      return Error{path + ": mapping." + truncate_token(role) + ": " +
                   unknown_message("role", role, roles)};
    }
  }
  m.override_with(*file);
  return Ok{};
}

// --time COLUMN[:UNIT]: the time role "t", which every scenario has.
Status apply_time_arg(const std::string& text, Mapping& m) {
  std::string col = text, unit;
  if (const auto colon = col.rfind(':');
      colon != std::string::npos && is_time_unit(col.substr(colon + 1))) {
    unit = col.substr(colon + 1);
    col.erase(colon);
  }
  if (col.empty()) return Error{"--time: expected COLUMN[:UNIT], got " + quote_token(text)};
  if (auto st = check_iso_zone("--time", unit); !st) return st;
  RoleMapping& r = m["t"];
  r.column = col;
  if (!unit.empty()) r.unit = unit == "s" ? "" : unit;
  return Ok{};
}

// --unit ROLE=UNIT: a unit kfw converts from ('iso' for the time only).
Status check_unit_arg(const std::string& text, const KeyValue& kv) {
  if (is_iso_unit(kv.value) && kv.key != "t") {
    return Error{"--unit " + text + ": 'iso' is for the time 't' only"};
  }
  if (auto st = check_iso_zone("--unit " + text, kv.value); !st) return st;
  if (!is_iso_unit(kv.value)) {
    if (auto f = unit_factor(kv.value, kv.value == "s" ? "ms" : "s");
        !f && f.error().rfind("unknown unit", 0) == 0) {
      return Error{"--unit " + text + ": " + f.error()};
    }
  }
  return Ok{};
}

// --map, --unit, --scale, --offset and --flip: each changes one field of one of `roles`.
Status apply_role_args(const ImportArgs& imp, const std::vector<std::string>& roles, Mapping& m) {
  auto role = [&](const std::string& opt, const std::string& name) -> Expected<RoleMapping*> {
    if (std::find(roles.begin(), roles.end(), name) == roles.end()) {
      return Error{opt + ": " + unknown_message("role", name, roles)};
    }
    return &m[name];
  };
  for (const auto& text : imp.map) {
    auto kv = split_kv("--map", text, "ROLE=COLUMN");
    if (!kv) return kv.err();
    auto r = role("--map", kv->key);
    if (!r) return r.err();
    (*r)->column = kv->value;
  }
  for (const auto& text : imp.unit) {
    auto kv = split_kv("--unit", text, "ROLE=UNIT");
    if (!kv) return kv.err();
    auto r = role("--unit", kv->key);
    if (!r) return r.err();
    if (auto st = check_unit_arg(text, *kv); !st) return st;
    (*r)->unit = kv->value;
  }
  for (const auto& text : imp.scale) {
    auto kv = split_kv("--scale", text, "ROLE=X");
    if (!kv) return kv.err();
    auto r = role("--scale", kv->key);
    if (!r) return r.err();
    auto v = number("--scale", *kv);
    if (!v) return v.err();
    if (*v == 0.0) return Error{"--scale " + text + ": must not be 0"};
    (*r)->scale = *v;
  }
  for (const auto& text : imp.offset) {
    auto kv = split_kv("--offset", text, "ROLE=X");
    if (!kv) return kv.err();
    auto r = role("--offset", kv->key);
    if (!r) return r.err();
    auto v = number("--offset", *kv);
    if (!v) return v.err();
    (*r)->offset = *v;
  }
  for (const auto& name : imp.flip) {
    auto r = role("--flip", name);
    if (!r) return r.err();
    (*r)->flip = true;
  }
  // A role touched only by --unit/--scale/... reads the column of its own name.
  return Ok{};
}

}  // namespace

Status apply_import_args(const ImportArgs& imp, const std::vector<ColumnSpec>& roles, Mapping& m) {
  std::vector<std::string> names;
  for (const auto& c : roles_with_time(roles))
    names.push_back(c.name);
  if (imp.mapping_file) {
    if (auto st = apply_mapping_file(*imp.mapping_file, names, m); !st) return st;
  }
  if (auto st = apply_format_args(imp, m); !st) return st;
  if (imp.time) {
    if (auto st = apply_time_arg(*imp.time, m); !st) return st;
  }
  return apply_role_args(imp, names, m);
}

Status apply_import_args(const ImportArgs& imp, Workspace& ws) {
  // They say how to read a file: with none in force (the run simulates) they would be ignored.
  if (!ws.data_path && imp.any()) {
    const char* opt = !imp.map.empty()      ? "--map"
                      : imp.time            ? "--time"
                      : !imp.unit.empty()   ? "--unit"
                      : !imp.scale.empty()  ? "--scale"
                      : !imp.offset.empty() ? "--offset"
                      : !imp.flip.empty()   ? "--flip"
                      : imp.mapping_file    ? "--mapping"
                      : imp.sep             ? "--sep"
                                            : "--header";
    return Error{std::string(opt) +
                 ": applies to file data (--data FILE, or a preset's \"data\"), " +
                 "and this run simulates its data"};
  }
  if (auto st = apply_import_args(imp, ws.scenario->columns(), ws.mapping); !st) return st;
  if (imp.mapping_file) ws.mapping_path = imp.mapping_file;
  return Ok{};
}

}  // namespace kfw
