// Issue 28: the library's IMM files (presets/models/cv_imm.json, cv_ct_imm.json) over 20 seeds:
// consistent (NEES/dof and NIS/dof near 1) and better than one filter of the same family.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "common/model_files.h"
#include "core/scenario.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

struct McMeans {
  double rmse = 0.0, nees = 0.0, nis = 0.0;
};

// Means over seeds 1..20 of rmse, nees_mean and nis_mean, `change` applied to the values.
template <class Change>
McMeans monte_carlo(const Scenario& s, Change change) {
  McMeans m;
  const int seeds = 20;
  for (int seed = 1; seed <= seeds; ++seed) {
    ParamValues v = s.params().defaults();
    v["sim.seed"] = seed;
    auto d = s.simulate(v);
    EXPECT_TRUE(d.ok()) << d.error();
    if (!d.ok()) return m;
    change(v);
    auto r = s.run(*d, v);
    EXPECT_TRUE(r.ok()) << r.error();
    if (!r.ok()) return m;
    m.rmse += r->get()->metrics.at("rmse") / seeds;
    m.nees += r->get()->metrics.at("nees_mean") / seeds;
    m.nis += r->get()->metrics.at("nis_mean") / seeds;
  }
  return m;
}

TEST(ImmModelLibrary, TwoNoiseLevelsBeatTheBestSingleLevel) {
  // Both modes at q_man is one Kalman filter (the best single level over 50 seeds, 7.07 m).
  auto s = testing::load_model("cv_imm.json");
  ASSERT_TRUE(s);
  const McMeans imm = monte_carlo(*s, [](ParamValues&) {});
  const McMeans one = monte_carlo(*s, [](ParamValues& v) { v["q_quiet"] = v["q_man"]; });
  EXPECT_LT(imm.rmse, 0.95 * one.rmse) << imm.rmse << " vs " << one.rmse;
  EXPECT_GT(imm.nees, 0.5);
  EXPECT_LT(imm.nees, 1.5);
  EXPECT_GT(imm.nis, 0.7);
  EXPECT_LT(imm.nis, 1.3);
}

TEST(ImmModelLibrary, ConstantVelocityAndTurnBeatTheTurnModelAlone) {
  const std::string path = testing::kModelDir + "cv_ct_imm.json";
  auto s = testing::load_model_file(path);
  ASSERT_TRUE(s);
  // The turn model alone: the file without modes, its process the turn mode's.
  std::ifstream in(path);
  auto j = nlohmann::json::parse(in);
  auto& m = j["model"];
  m["process"] = m["modes"]["list"][1]["process"];
  m.erase("modes");
  j["parameters"].erase("markov.stay");
  auto ct = make_model_scenario(j, "ct_only.json");
  ASSERT_TRUE(ct.ok()) << ct.error();
  for (double filter : {0.0, 1.0}) {  // ekf, ukf
    const auto set = [filter](ParamValues& v) { v["filter"] = filter; };
    const McMeans imm = monte_carlo(*s, set);
    const McMeans one = monte_carlo(**ct, set);
    EXPECT_LT(imm.rmse, 0.97 * one.rmse) << imm.rmse << " vs " << one.rmse;
    EXPECT_GT(imm.nees, 0.7);
    EXPECT_LT(imm.nees, 1.5);
    EXPECT_GT(imm.nis, 0.7);
    EXPECT_LT(imm.nis, 1.3);
  }
}

}  // namespace
}  // namespace kfw
