// Every scenario runs at the shortest simulation its table allows: exit 0, every metric finite,
// and every metric it cannot compute listed as undefined with a reason (never null or NaN).
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario.h"

namespace kfw {
namespace {

TEST(DurationMinimum, EveryScenarioRunsAtItsShortestSimulation) {
  int ran = 0;
  for (const auto& name : scenarios().names()) {
    auto s = make_scenario(name);
    ASSERT_TRUE(s.ok()) << name;
    const ParamSpec* spec = (*s)->params().find("sim.duration");
    if (!spec) continue;
    ParamValues v = (*s)->params().defaults();
    v["sim.duration"] = spec->min;
    if (const ParamSpec* step = (*s)->params().find("sim.step_time")) {
      v["sim.step_time"] = std::min(v["sim.step_time"], 0.5 * spec->min);  // inside the run
      ASSERT_GE(v["sim.step_time"], step->min) << name;
    }
    auto d = (*s)->simulate(v);
    ASSERT_TRUE(d.ok()) << name << ": " << d.error();
    auto r = (*s)->run(*d, v);
    ASSERT_TRUE(r.ok()) << name << ": " << r.error();
    ++ran;
    for (const auto& [k, x] : (*r)->metrics)
      EXPECT_TRUE(std::isfinite(x)) << name << " " << k;
    for (const auto& [k, why] : (*r)->undefined) {
      EXPECT_FALSE(why.empty()) << name << " " << k;
      EXPECT_EQ((*r)->metrics.count(k), 0u) << name << " " << k;
    }
  }
  EXPECT_GE(ran, 4);  // helicopter, radome, ballbeam, underwater
}

}  // namespace
}  // namespace kfw
