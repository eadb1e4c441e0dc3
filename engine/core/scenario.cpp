#include "core/scenario.h"

namespace kfw {

void register_all_scenarios(ScenarioRegistry& registry);  // generated: scenario_list.cpp

Expected<Metrics> Scenario::gain(const ParamValues&, const Dataset*) const {
  return Error{"scenario '" + name() + "' has no steady-state gain"};
}

Expected<std::string> Scenario::command(const std::string& cmd, const Dataset&,
                                        const ParamValues&) const {
  return Error{"scenario '" + name() + "' has no command '" + cmd + "'"};
}

void ScenarioRegistry::add(std::string name, Factory factory) {
  factories_[std::move(name)] = std::move(factory);
}

std::vector<std::string> ScenarioRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, f] : factories_)
    out.push_back(name);
  return out;
}

std::unique_ptr<Scenario> ScenarioRegistry::make(const std::string& name) const {
  auto it = factories_.find(name);
  return it == factories_.end() ? nullptr : it->second();
}

const ScenarioRegistry& scenarios() {
  static const ScenarioRegistry registry = [] {
    ScenarioRegistry r;
    register_all_scenarios(r);
    return r;
  }();
  return registry;
}

Expected<std::unique_ptr<Scenario>> make_scenario(const std::string& name) {
  auto s = scenarios().make(name);
  if (!s) {
    std::string msg = "unknown scenario '" + name + "'; known:";
    for (const auto& n : scenarios().names())
      msg += " " + n;
    return Error{msg};
  }
  return s;
}

}  // namespace kfw
