// Issue 27: sub-expressions of parameters, dt and inputs that expressions of states read are
// evaluated once per step (Expr::state_text, ModelEval's step-level groups) instead of expanded
// into every entry and evaluated at every linearisation and sigma point. Seed 004's rotation of
// the DVL velocity is such a sub-expression; a run must not change by it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/scenario.h"
#include "model/expression.h"
#include "model/model_scenario.h"

namespace kfw::model {
namespace step_subs_test {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/underwater.json";

TEST(ModelStepSubs, AStateExpressionKeepsItsStepLevelSubExpressionsByName) {
  Symbols s;
  s.add("q", kParamSymbol);
  s.add("dt", kDtSymbol);
  s.add("t", kTimeSymbol);
  s.add("x", kStateSymbol);
  s.add("u", kInputSymbol);
  auto a = compile_expr("cos(u)", "a", s, kAllSymbols, "");
  ASSERT_TRUE(a.ok());
  const int sa = s.add_sub("ca", *a);
  auto b = compile_expr("ca*dt + q", "b", s, kAllSymbols, "");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->state_text, "ca*dt + q");  // a step-level sub-expression reads the one before
  const int sb = s.add_sub("vb", *b);
  auto c = compile_expr("t*u", "c", s, kAllSymbols, "");
  ASSERT_TRUE(c.ok());
  s.add_sub("tu", *c);

  auto f = compile_expr("x + vb + tu", "f", s, kAllSymbols, "");
  ASSERT_TRUE(f.ok()) << f.error();
  EXPECT_EQ(f->dep, Dep::kState);
  EXPECT_EQ(f->state_text, "x + vb + (t*u)");  // of t: expanded (RK4 moves t within a step)
  EXPECT_EQ(f->step_subs, (std::vector<int>{sa, sb}));
  EXPECT_EQ(f->text, "x + ((cos(u))*dt + q) + (t*u)");  // what GiNaC differentiates

  auto g = compile_expr("x + tu", "g", s, kAllSymbols, "");
  ASSERT_TRUE(g.ok());
  EXPECT_TRUE(g->state_text.empty());
  EXPECT_TRUE(g->step_subs.empty());
}

// The file as shipped against the same file with every sub-expression made to depend on t (so
// that each is expanded into the entries as before): the EKF in each scheme and the UKF agree.
TEST(ModelStepSubs, RunsEqualTheExpandedSubExpressions) {
  std::ifstream in(kFile);
  const auto j = nlohmann::json::parse(in);
  nlohmann::json expanded = j;
  for (auto& [name, e] : expanded["model"]["expressions"].items())
    e = "(" + e.get<std::string>() + ") + 0*t";
  auto a = make_model_scenario(j, kFile);
  auto b = make_model_scenario(expanded, "expanded.json");
  ASSERT_TRUE(a.ok() && b.ok());
  ParamValues v = (*a)->params().defaults();
  v["sim.duration"] = 30;
  auto d = (*a)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  const auto& filters = (*a)->params().find("filter")->choices;
  for (double scheme : {0.0, 2.0}) {
    for (std::size_t f = 0; f < filters.size(); ++f) {
      SCOPED_TRACE(filters[f] + " scheme " + std::to_string(scheme));
      v["scheme"] = scheme;
      v["filter"] = static_cast<double>(f);
      auto ra = (*a)->run(*d, v);
      auto rb = (*b)->run(*d, v);
      ASSERT_TRUE(ra.ok() && rb.ok());
      const Dataset ta = (*ra)->table(), tb = (*rb)->table();
      for (const char* col : {"x.x", "x.y", "x.z", "P.x", "P.x.y", "P.z"}) {
        for (std::size_t k = 0; k < ta.rows(); ++k) {
          const double x = ta.col(col)[k], y = tb.col(col)[k];
          ASSERT_NEAR(x, y, 1e-12 * (1 + std::fabs(y))) << col << " row " << k;
        }
      }
    }
  }
}

}  // namespace
}  // namespace step_subs_test
}  // namespace kfw::model
