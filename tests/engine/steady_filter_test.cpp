// Issue 30: filter = steady — the fixed DARE gain of a linear time-invariant model with one
// channel. On cv1d its gain at every update is `kfw-cli gain`'s K, its estimates join the KF's
// once the KF has converged (1e-9 in ../shared/STAGE.md's form), a channel updated every m-th
// row uses the m-step gain, and a model it cannot run is refused naming the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/model_files.h"
#include "core/scenario.h"
#include "model/model_result.h"

namespace kfw {
namespace {

std::shared_ptr<const model::ModelResult> run(const Scenario& s, const Dataset& d, ParamValues v) {
  auto r = s.run(d, v);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  return r.ok() ? std::dynamic_pointer_cast<const model::ModelResult>(*r) : nullptr;
}

TEST(SteadyFilter, UsesTheDareGainAndJoinsTheConvergedKf) {
  auto s = testing::load_model("cv1d.json");
  ASSERT_TRUE(s);
  const ParamSpec* f = s->params().find("filter");
  ASSERT_TRUE(f);
  ASSERT_EQ(f->choices.back(), "steady");
  ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto g = s->gain(v, &*d);
  ASSERT_TRUE(g.ok()) << g.error();
  v["filter"] = 0.0;  // kf
  auto kf = run(*s, *d, v);
  v["filter"] = static_cast<double>(f->choices.size() - 1);
  auto steady = run(*s, *d, v);
  ASSERT_TRUE(kf && steady);
  EXPECT_EQ(steady->filter, "steady");
  const auto& Kx = steady->chans[0].K[0];  // K.x.z
  const auto& Kv = steady->chans[0].K[1];  // K.v.z
  std::size_t updates = 0;
  for (std::size_t k = 0; k < Kx.size(); ++k) {
    if (!std::isfinite(Kx[k])) continue;
    ++updates;
    EXPECT_DOUBLE_EQ(Kx[k], g->at("K.x.z"));
    EXPECT_DOUBLE_EQ(Kv[k], g->at("K.v.z"));
  }
  EXPECT_GT(updates, kf->steps() / 2);
  // The KF's transient decays: the two estimates draw together, to a small part of σ.
  const std::size_t n = kf->steps();
  const auto gap = [&](std::size_t k) {
    return std::fabs(steady->x[0][k] - kf->x[0][k]) / std::sqrt(kf->P[kf->diag[0]][k]);
  };
  EXPECT_LT(gap(n - 1), 0.1 * gap(n / 10));
  EXPECT_LT(gap(n - 1), 1e-3);
}

TEST(SteadyFilter, AChannelEveryMthRowUsesTheMStepGain) {
  std::ifstream in(testing::kModelDir + "cv1d.json");
  auto j = nlohmann::json::parse(in);
  j["model"]["measurements"]["position"]["every"] = 5;
  auto s = make_model_scenario(j, "cv1d_every5.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  auto g = (*s)->gain(v);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->at("every"), 5.0);
  v["filter"] = 3.0;  // steady
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = run(**s, *d, v);
  ASSERT_TRUE(r);
  for (std::size_t k = 0; k < r->steps(); ++k) {
    const double K = r->chans[0].K[0][k];
    EXPECT_EQ(std::isfinite(K), k % 5 == 0) << k;
    if (std::isfinite(K)) {
      EXPECT_NEAR(K, g->at("K.x.z"), 1e-12);  // the data's median dt against sim.dt
    }
  }
}

TEST(SteadyFilter, IsOfferedOnlyWhereADareGainExists) {
  // A nonlinear model (range-bearing) and a two-channel one have no single fixed gain.
  for (const char* name : {"range_bearing.json", "helicopter_indirect.json"}) {
    auto s = testing::load_model(name);
    ASSERT_TRUE(s);
    const auto& choices = s->params().find("filter")->choices;
    EXPECT_EQ(std::find(choices.begin(), choices.end(), "steady") != choices.end(),
              std::string(name) == "helicopter_indirect.json")
        << name;
  }
  std::ifstream in(testing::kModelDir + "cv1d.json");
  auto j = nlohmann::json::parse(in);
  j["parameters"]["filter"] = {{"value", "steady"}, {"choices", {"kf", "steady", "ukff"}}};
  auto bad = make_model_scenario(j, "cv1d.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("parameters.filter.choices[2]: 'ukff' is not a filter"),
            std::string::npos)
      << bad.error();
}

}  // namespace
}  // namespace kfw
