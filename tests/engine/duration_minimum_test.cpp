// Every shipped model file runs at the shortest simulation its table allows: exit 0, every metric
// finite, and every metric it cannot compute listed as undefined with a reason (never null or NaN).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/scenario.h"
#include "document/preset.h"

namespace kfw {
namespace {

std::vector<std::string> duration_minimum_presets() {
  std::vector<std::string> paths;
  for (const char* dir : {"/presets", "/presets/models"}) {
    for (const auto& e : std::filesystem::directory_iterator(std::string(KFW_SOURCE_DIR) + dir))
      if (e.path().extension() == ".json") paths.push_back(e.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

TEST(DurationMinimum, EveryScenarioRunsAtItsShortestSimulation) {
  int ran = 0;
  for (const auto& name : duration_minimum_presets()) {
    auto p = load_preset(name);
    ASSERT_TRUE(p.ok()) << name << ": " << p.error();
    const Scenario* s = p->instance.get();
    const ParamSpec* spec = s->params().find("sim.duration");
    if (!spec) continue;
    ParamValues v = p->values;
    v["sim.duration"] = spec->min;
    if (const ParamSpec* step = s->params().find("sim.step_time")) {
      v["sim.step_time"] = std::min(v["sim.step_time"], 0.5 * spec->min);  // inside the run
      ASSERT_GE(v["sim.step_time"], step->min) << name;
    }
    auto d = s->simulate(v);
    ASSERT_TRUE(d.ok()) << name << ": " << d.error();
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << name << ": " << r.error();
    ++ran;
    for (const auto& [k, x] : (*r)->metrics)
      EXPECT_TRUE(std::isfinite(x)) << name << " " << k;
    for (const auto& [k, why] : (*r)->undefined) {
      EXPECT_FALSE(why.empty()) << name << " " << k;
      EXPECT_EQ((*r)->metrics.count(k), 0u) << name << " " << k;
    }
  }
  EXPECT_GE(ran, 5);  // the four seeds and the models/ examples
}

}  // namespace
}  // namespace kfw
