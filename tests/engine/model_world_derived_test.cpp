// Issue 27, derived quantities: named expressions of a run. A scalar of parameters and dt — here
// the α of the α-β filter from Kalata's tracking index λ = σ_a T²/σ_r, written with
// sub-expressions — equals the DARE's steady gain K.x.z; a series of estimates and truth — the
// position error — has an RMS equal to the engine's rmse.x.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

using nlohmann::json;

json cv1d_with_derived() {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/cv1d.json");
  json p = json::parse(in);
  p["model"]["version"] = 2;
  p["model"]["expressions"] = {{"lam", "sigma_a*dt^2/sigma_r"},
                               {"rr", "(4 + lam - sqrt(8*lam + lam^2))/4"}};
  p["model"]["derived"] = json::parse(R"J({
    "lambda": {"expression": "lam", "label": "tracking index λ"},
    "alpha": {"expression": "1 - rr^2", "label": "α (Kalata)"},
    "err_x": {"expression": "x - x_true", "unit": "m", "label": "position error"}
  })J");
  return p;
}

TEST(ModelWorldDerived, ScalarsAndSeriesOfARun) {
  auto s = make_model_scenario(cv1d_with_derived(), "cv1d.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const Metrics& m = (*r)->metrics;
  const double T = v.at("sim.dt");
  EXPECT_NEAR(m.at("derived.lambda"), v.at("sigma_a") * T * T / v.at("sigma_r"), 1e-15);
  auto g = (*s)->gain(v, nullptr);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_NEAR(m.at("derived.alpha"), g->at("K.x.z"), 1e-9 * g->at("K.x.z"));
  EXPECT_NEAR(m.at("derived.err_x.rms"), m.at("rmse.x"), 1e-12 * m.at("rmse.x"));
  EXPECT_GE(m.at("derived.err_x.max"), m.at("derived.err_x.rms"));
  const Dataset table = (*r)->table();
  ASSERT_TRUE(table.has("derived.err_x"));
  EXPECT_NEAR(table.col("derived.err_x")[5], table.col("x.x")[5] - table.col("truth.x")[5], 1e-15);
  // Declared once: the metrics table, Tune and Sweep read these specs.
  int declared = 0;
  for (const auto& spec : (*s)->metric_specs()) {
    declared += spec.key == "derived.alpha" || spec.key == "derived.err_x.rms" ||
                spec.key == "derived.err_x.max";
  }
  EXPECT_EQ(declared, 3);
}

TEST(ModelWorldDerived, WithoutTruthTheSeriesMetricsAreUndefinedNotNaN) {
  auto s = make_model_scenario(cv1d_with_derived(), "cv1d.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  Dataset no_truth = *d;
  for (auto& x : no_truth.columns[static_cast<std::size_t>(no_truth.index("x_true"))])
    x = kNoSample;
  auto r = (*s)->run(no_truth, v);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ((*r)->metrics.count("derived.err_x.rms"), 0u);
  EXPECT_EQ((*r)->undefined.at("derived.err_x.rms"), "no finite value in the run");
}

TEST(ModelWorldDerived, MistakesAreNamed) {
  json p = cv1d_with_derived();
  p["model"]["derived"]["bad"] = "x + nope";
  auto s = make_model_scenario(p, "cv1d.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().rfind("cv1d.json: model.derived.bad: unknown symbol 'nope'", 0), 0u)
      << s.error();
  p = cv1d_with_derived();
  p["model"]["derived"]["alpha"]["colour"] = "red";
  s = make_model_scenario(p, "cv1d.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().rfind("cv1d.json: model.derived.alpha.colour: unknown key", 0), 0u)
      << s.error();
  // Truth columns are symbols of derived quantities only.
  p = cv1d_with_derived();
  p["model"]["process"]["F"][0][1] = "x_true";
  s = make_model_scenario(p, "cv1d.json");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("model.process.F[0][1]: unknown symbol 'x_true'"), std::string::npos)
      << s.error();
  p = cv1d_with_derived();
  p["model"].erase("expressions");
  p["model"]["derived"] = {{"lambda", "sigma_a*dt^2/sigma_r"}};
  p["model"]["version"] = 1;
  s = make_model_scenario(p, "cv1d.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(), "cv1d.json: model.derived: a version-2 key: set \"version\": 2");
}

}  // namespace
}  // namespace kfw
