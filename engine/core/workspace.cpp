#include "core/workspace.h"

#include <filesystem>

namespace kfw {

Expected<Workspace> open_workspace(const std::string& preset,
                                   const std::optional<std::string>& data,
                                   const std::vector<std::string>& assignments) {
  auto p = load_preset(resolve_preset_path(preset));
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

Expected<Dataset> load_dataset_file(const Scenario& scenario, const std::string& path,
                                    const Mapping& mapping) {
  CsvOptions opt;
  const auto columns = scenario.columns();
  // Time is the role "t"; the mapping may name another column for it.
  if (auto t = mapping.find("t"); t != mapping.end() && !t->second.column.empty()) {
    opt.time_column = t->second.column;
  }
  for (const auto& c : columns) {
    auto m = mapping.find(c.name);
    opt.validate.push_back(m == mapping.end() || m->second.column.empty() ? c.name
                                                                          : m->second.column);
  }
  auto d = read_csv(path, opt);
  if (!d) return d;
  std::map<std::string, std::string> units;
  for (const auto& c : columns)
    units[c.name] = c.unit;
  units["t"] = "s";
  auto mapped = apply_mapping(std::move(*d), mapping, units);
  if (!mapped) return mapped;
  if (auto st = require_columns(*mapped, columns); !st) return st.err();
  if (auto st = require_some_value(*mapped, columns); !st) return st.err();
  return mapped;
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
