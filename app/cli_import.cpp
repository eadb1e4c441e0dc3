// kfw-cli's `inspect` command. The import options it shares with every command and with kfw are
// declared and applied in document/import_args.h.
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
  } else if (a.import.any_role()) {
    return fail(err, Error{"inspect: role options (--map, --unit, ...) need a PRESET: "
                           "kfw-cli inspect FILE PRESET"});
  } else if (auto st = apply_import_args(a.import, {}, given); !st) {
    return fail(err, st.err());  // the format (--sep, --header) and --time
  }
  auto t = read_table(a.file, given.table_options());
  if (!t) return fail(err, t.err());
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
