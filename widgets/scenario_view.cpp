#include "scenario_view.h"

namespace kfw {

void register_all_views(ViewRegistry& registry);  // generated: view_list.cpp

std::unique_ptr<ScenarioView> ViewRegistry::make(const std::string& scenario) const {
  auto it = factories_.find(scenario);
  return it == factories_.end() ? nullptr : it->second();
}

const ViewRegistry& views() {
  static const ViewRegistry registry = [] {
    ViewRegistry r;
    register_all_views(r);
    return r;
  }();
  return registry;
}

}  // namespace kfw
