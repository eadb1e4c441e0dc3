#include "core/workspace.h"

namespace kfw {

Expected<Workspace> open_workspace(const std::string& preset,
                                   const std::optional<std::string>& data,
                                   const std::vector<std::string>& assignments) {
  auto p = load_preset(resolve_preset_path(preset));
  if (!p) return Error{p.error()};
  auto s = make_scenario(p->scenario);
  if (!s) return Error{s.error()};
  Workspace ws;
  ws.preset = std::move(*p);
  ws.scenario = std::shared_ptr<const Scenario>(std::move(*s));
  ws.values = ws.preset.values;
  for (const auto& a : assignments) {
    if (auto st = ws.scenario->params().apply_assignment(a, ws.values); !st)
      return Error{st.error()};
  }
  ws.data_path = data ? data : ws.preset.data_path;
  return ws;
}

Expected<Dataset> load_dataset_file(const Scenario& scenario, const std::string& path) {
  auto d = read_csv(path);
  if (!d) return d;
  if (auto st = require_columns(*d, scenario.columns()); !st) return Error{st.error()};
  return d;
}

Expected<Dataset> load_dataset(const Workspace& ws) {
  if (ws.data_path) return load_dataset_file(*ws.scenario, *ws.data_path);
  return ws.scenario->simulate(ws.values);
}

}  // namespace kfw
