// kfw-cli's import options (--map, --unit, --time, --scale, --offset, --flip, --sep, --header,
// --mapping) and the `inspect` command. Declared with the other options in cli.cpp.
#include <fast_float/fast_float.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_commands.h"
#include "core/suggest.h"
#include "data/import.h"
#include "data/json_io.h"
#include "document/preset.h"
#include "document/workspace.h"

namespace kfw {

namespace {

using Json = nlohmann::ordered_json;

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

namespace {

struct TimeSummary {
  std::string column, unit, error, origin;
  double start = 0.0, end = 0.0, median_dt = 0.0, min_dt = 0.0, max_dt = 0.0;
};

TimeSummary summarize_time(const Table& t, const Mapping& m) {
  TimeSummary s;
  auto it = m.find("t");
  if (it == m.end() && t.index("t") < 0) {
    s.error = "no time column found (give one: --time COLUMN[:UNIT])";
    return s;
  }
  Mapping only_t;
  if (it != m.end()) only_t["t"] = it->second;
  s.column = it == m.end() || it->second.column.empty() ? "t" : it->second.column;
  s.unit = it == m.end() || it->second.unit.empty() ? "s" : it->second.unit;
  auto d = import_table(t, only_t, {});
  if (!d) {
    s.error = d.error();
    return s;
  }
  const auto& time = d->col("t");
  s.start = time.front();
  s.end = time.back();
  s.median_dt = d->median_dt();
  s.origin = d->time_origin;
  if (time.size() > 1) {
    s.min_dt = s.max_dt = time[1] - time[0];
    for (std::size_t i = 2; i < time.size(); ++i) {
      s.min_dt = std::min(s.min_dt, time[i] - time[i - 1]);
      s.max_dt = std::max(s.max_dt, time[i] - time[i - 1]);
    }
  }
  return s;
}

std::string num(double v) {
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

// What inspect found: the table, the mapping (the guess with the given one over it), the
// required roles without a column and the time column's summary; `scenario` and `preset` (the
// PRESET as given: a shipped name or a file's stem) are empty without a PRESET.
struct Inspection {
  Table table;
  Mapping mapping;
  std::vector<std::string> missing;
  TimeSummary time;
  std::string scenario, preset;
};

void print_inspection_json(const std::string& file, const Inspection& in, std::ostream& out) {
  const Table& t = in.table;
  const TimeSummary& ts = in.time;
  Json j;
  j["file"] = file;
  j["separator"] = t.separator_name();
  j["decimal_comma"] = t.decimal_comma;
  j["header_line"] = t.header_line;  // 0: no header (columns col1, col2, ...)
  j["header"] = t.has_header() ? "first" : "none";
  j["rows"] = t.rows();
  Json cols = Json::array();
  for (std::size_t c = 0; c < t.columns(); ++c) {
    Json col;
    col["name"] = t.names[c];
    col["not_numbers"] = t.invalid[c];
    col["unit_from_name"] = unit_from_name(t.names[c]);
    cols.push_back(col);
  }
  j["columns"] = cols;
  Json time;
  time["column"] = ts.column;
  time["unit"] = ts.unit;
  if (ts.error.empty()) {
    time["start_s"] = ts.start;
    time["end_s"] = ts.end;
    time["span_s"] = ts.end - ts.start;
    if (std::isfinite(ts.median_dt)) {
      time["median_step_s"] = ts.median_dt;
      time["min_step_s"] = ts.min_dt;
      time["max_step_s"] = ts.max_dt;
      time["rate_hz"] = ts.median_dt > 0 ? 1.0 / ts.median_dt : 0.0;
    } else {
      time["rate_undefined"] = "fewer than two time samples";
    }
    if (!ts.origin.empty()) time["origin"] = ts.origin;
  } else {
    time["error"] = ts.error;
  }
  j["time"] = time;
  if (!in.scenario.empty()) j["scenario"] = in.scenario;
  if (!in.preset.empty()) j["preset"] = in.preset;
  j["mapping"] = mapping_to_json(in.mapping);
  j["missing"] = in.missing;
  out << j.dump(2) << "\n";
}

void print_inspection_text(const std::string& file, const Inspection& in, std::ostream& out) {
  const Table& t = in.table;
  const TimeSummary& ts = in.time;
  out << "file: " << file << "\n";
  out << "separator: " << t.separator_name() << (t.decimal_comma ? " (decimal comma)" : "") << "\n";
  out << "rows: " << t.rows();
  if (t.has_header())
    out << " (header on line " << t.header_line << ")\n";
  else
    out << " (no header: columns named by position, col1 .. col" << t.columns() << ")\n";
  out << "columns: " << t.columns() << "\n";
  for (std::size_t c = 0; c < t.columns(); ++c) {
    out << "  " << std::setw(3) << c + 1 << "  " << t.names[c];
    if (const auto u = unit_from_name(t.names[c]); !u.empty()) out << "  [" << u << "]";
    if (t.invalid[c] > 0) {
      out << "  (" << t.invalid[c] << " cells not numbers, first at line "
          << t.first_invalid[c].line << ")";
    }
    out << "\n";
  }
  if (ts.error.empty()) {
    out << "time: column '" << ts.column << "' (" << ts.unit << "), " << num(ts.start) << " .. "
        << num(ts.end) << " s, span " << num(ts.end - ts.start) << " s\n";
    if (std::isfinite(ts.median_dt)) {
      const double rate = ts.median_dt > 0 ? 1.0 / ts.median_dt : 0.0;
      out << "rate: " << num(rate) << " Hz (median step " << num(ts.median_dt) << " s, min "
          << num(ts.min_dt) << ", max " << num(ts.max_dt) << ")\n";
    } else {
      out << "rate: undefined (fewer than two time samples)\n";
    }
    if (!ts.origin.empty()) out << "time origin: " << ts.origin << " (t = 0)\n";
  } else {
    out << "time: " << ts.error << "\n";
  }
  if (in.scenario.empty()) {
    out << "mapping: give a PRESET to guess its roles (kfw-cli inspect FILE PRESET)\n";
    return;
  }
  out << "mapping for " << in.preset << ": " << mapping_options(in.mapping) << "\n";
  out << "mapping block: " << mapping_to_json(in.mapping).dump() << "\n";
  if (in.missing.empty()) {
    out << "complete: every required role has a column\n";
  } else {
    out << "missing required roles:";
    for (const auto& m : in.missing)
      out << " " << m;
    out << "\n";
  }
}

}  // namespace

int cmd_inspect(const InspectArgs& a, std::ostream& out, std::ostream& err) {
  // The roles: the preset's (or scenario's), else time alone; the format: the preset's mapping's
  // (with the options over it), else the options'.
  std::vector<ColumnSpec> roles;
  Mapping given;
  Inspection in;
  if (a.preset) {
    auto ws = open_workspace_for_cli(TargetArgs{*a.preset, {}}, DataArgs{a.file, a.import}, err);
    if (!ws) return fail(err, ws.err());
    roles = ws->scenario->columns();
    given = ws->mapping;
    in.scenario = ws->scenario->name();
    in.preset = std::filesystem::path(*a.preset).stem().string();
  } else if (auto st = apply_format_args(a.import, given); !st) {
    return fail(err, st.err());
  }
  auto t = read_table(a.file, given.table_options());
  if (!t) return fail(err, t.err());
  if (!a.preset && a.import.any_role()) {
    return fail(err, Error{"inspect: role options (--map, --unit, ...) need a PRESET: "
                           "kfw-cli inspect FILE PRESET"});
  }
  if (!a.preset && a.import.time) {
    if (auto st = apply_time_arg(*a.import.time, given); !st) return fail(err, st.err());
  }
  in.table = std::move(*t);
  in.mapping = guess_mapping(in.table, roles);
  in.mapping.override_with(given);
  for (const auto& c : roles_with_time(roles)) {
    if (c.required && role_column(in.table, in.mapping, c.name) < 0) in.missing.push_back(c.name);
  }
  in.time = summarize_time(in.table, in.mapping);
  if (a.json) {
    print_inspection_json(a.file, in, out);
  } else {
    print_inspection_text(a.file, in, out);
  }
  return kExitOk;
}

}  // namespace kfw
