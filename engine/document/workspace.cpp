#include "document/workspace.h"

#include <filesystem>

#include "data/import.h"
#include "document/command_line.h"

namespace kfw {

Expected<Workspace> open_workspace(const std::string& preset,
                                   const std::optional<std::string>& data,
                                   const std::vector<std::string>& assignments) {
  const std::string path = resolve_preset_path(preset);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    if (const std::string hint = preset_name_hint(preset); !hint.empty())
      return Error{preset + ": no preset of that name in " + preset_dir() + hint};
  }
  auto p = load_preset(path);
  if (!p) return p.err();
  Workspace ws;
  ws.preset = std::move(*p);
  ws.scenario = ws.preset.instance;
  ws.values = ws.preset.values;
  ws.mapping = ws.preset.mapping;
  for (const auto& a : assignments) {
    if (auto st = ws.scenario->params().apply_assignment(a, ws.values); !st) return st.err();
  }
  ws.data_from_preset = !data && ws.preset.data_path;
  ws.data_path = data ? data : ws.preset.data_path;
  return ws;
}

std::string mapping_options(const Mapping& m) {
  std::string s;
  for (const auto& a : mapping_args(m))
    s += (s.empty() ? "" : " ") + shell_quote(a);
  return s;
}

Expected<Dataset> import_dataset(const Scenario& scenario, const Table& table,
                                 const Mapping& mapping) {
  const auto columns = scenario.columns();
  // A required role that reads from no column: name it, and say what the guesser would map.
  for (const auto& c : roles_with_time(columns)) {
    if (!c.required || role_column(table, mapping, c.name) >= 0) continue;
    if (auto m = mapping.find(c.name); m != mapping.end() && !m->second.column.empty()) {
      continue;  // mapped to a column the file lacks: import_table names it
    }
    std::string msg = table.source + ": missing required column '" + c.name + "'";
    if (!c.meaning.empty()) msg += " (" + c.meaning + (c.unit.empty() ? "" : ", " + c.unit) + ")";
    msg += table.has_header() ? "; columns present:"
                              : "; no header (the first row is numbers), columns by position:";
    bool spaced = false;
    for (const auto& n : table.names) {
      msg += " " + (n.find_first_of(" \t") == std::string::npos ? n : "'" + n + "'");
      spaced = spaced || n.find_first_of(" \t") != std::string::npos;
    }
    // A name with blanks inside: the file is likely separated by spaces, or by tabs and spaces
    // mixed, and read with one separator.
    if (spaced && mapping.separator != kWhitespaceSeparator) {
      return Error{msg + "; a column name holds blanks: read the file with --sep whitespace"};
    }
    Mapping guess = guess_mapping(table, columns);
    guess.override_with(mapping);
    if (guess.count(c.name)) msg += "; map them, e.g. " + mapping_options(guess);
    return Error{msg};
  }
  auto d = import_table(table, mapping, columns);
  if (!d) return d;
  if (auto st = require_some_value(*d, columns); !st) return st.err();
  return d;
}

Expected<Dataset> load_dataset_file(const Scenario& scenario, const std::string& path,
                                    const Mapping& mapping) {
  auto t = read_table(path, mapping.table_options());
  if (!t) return t.err();
  return import_dataset(scenario, *t, mapping);
}

Expected<Dataset> load_dataset(const Workspace& ws) {
  if (!ws.data_path) return ws.scenario->simulate(ws.values);
  auto d = load_dataset_file(*ws.scenario, *ws.data_path, ws.mapping);
  if (!d && ws.data_from_preset) {
    std::error_code ec;
    if (!std::filesystem::exists(*ws.data_path, ec)) {
      return Error{ws.preset.path + ": data: " + *ws.data_path + ": no such file"};
    }
    // Not a file that opens (a directory, no permission): the preset's key is what to fix.
    if (!std::filesystem::is_regular_file(*ws.data_path, ec) ||
        d.error().find(": cannot open") != std::string::npos) {
      return Error{ws.preset.path + ": data: " + d.error()};
    }
  }
  return d;
}

}  // namespace kfw
