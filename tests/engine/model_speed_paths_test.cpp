// Issue 27, the underwater file's latency: the faster paths give what the plain ones gave.
// - fast_powers: a parenthesised base or a call raised to a literal 2 or 3, and a printed
//   derivative's ^(-0.5), go to products (muparser calls std::pow for them);
// - DerivedCache: the derived series that read no estimate are taken from the last run when
//   everything they read is bit for bit the same, and evaluated again when anything differs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "common/model_files.h"
#include "core/scenario.h"
#include "model/expression.h"
#include "model/model_result.h"

namespace kfw::model {
namespace speed_paths_test {
namespace {

TEST(FastPowers, RewritesOnlyParenthesisedBasesToALiteralTwoOrThree) {
  const std::pair<const char*, const char*> cases[] = {
      {"sqrt((15 - x)^2 + (15 - y)^2)", "sqrt(_pow2((15 - x)) + _pow2((15 - y)))"},
      {"cos(a)^3", "_pow3(cos(a))"},
      {"atan2(a, b) ^ 2 + 1", "_pow2(atan2(a, b)) + 1"},
      {"-(x)^2", "-_pow2((x))"},
      {"((a)^2 + 1)^2", "_pow2((_pow2((a)) + 1))"},
      {"b^(a)^2", "b^_pow2((a))"},
      {"((x*x)^(-0.5))", "(_rsqrt((x*x)))"},
      {"(x^(-0.5))", "(_rsqrt(x))"},
      // Left alone: muparser's own x^2, other exponents, a power of a power (x^2^3 = x^8),
      // numbers.
      {"x^2", "x^2"},
      {"(x)^2.5", "(x)^2.5"},
      {"(x)^20", "(x)^20"},
      {"(x)^2^3", "(x)^2^3"},
      {"(x)^4", "(x)^4"},
      {"2^(-0.5)", "2^(-0.5)"},
      {"(x)^y", "(x)^y"},
  };
  for (const auto& [in, want] : cases)
    EXPECT_EQ(fast_powers(in), want) << in;
}

// The values: those of std::pow to the last bit or two, and pow's own answers at its edges.
TEST(FastPowers, EvaluatesAsStdPowDoes) {
  Symbols s;
  s.add("x", kStateSymbol);
  s.add("y", kStateSymbol);
  const char* texts[] = {"(x + y)^2", "(x - y)^3", "((x*x + y*y)^(-0.5))", "-(x)^2"};
  std::vector<double> vars(2, 0.0), fast(4, 0.0), plain(4, 0.0);
  ExprGroup g;
  for (std::size_t i = 0; i < 4; ++i)
    g.add(texts[i], &fast[i]);
  ASSERT_TRUE(g.bind(s, vars.data()).ok());
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (int n = 0; n < 2000; ++n) {
    const double x = u(rng), y = u(rng);
    vars = {x, y};
    g.eval();
    plain = {std::pow(x + y, 2), std::pow(x - y, 3), std::pow(x * x + y * y, -0.5),
             -std::pow(x, 2)};
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_NEAR(fast[i], plain[i], 1e-15 * std::fabs(plain[i])) << texts[i] << " at " << x;
  }
  // 1/√x where pow says otherwise: ±0 → +∞, −∞ → 0, a negative → NaN.
  ExprGroup edge;
  double r = 0.0;
  edge.add("((x)^(-0.5))", &r);
  ASSERT_TRUE(edge.bind(s, vars.data()).ok());
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {0.0, -0.0, -inf, inf, -4.0}) {
    vars[0] = x;
    edge.eval();
    const double p = std::pow(x, -0.5);
    EXPECT_TRUE(r == p || (std::isnan(r) && std::isnan(p))) << x << ": " << r << " vs " << p;
  }
}

// The underwater file: five of its six derived series (range and depth errors) read no
// estimate. Runs through the scenario (which keeps a cache) equal add_derived without one.
TEST(DerivedCache, SeriesTakenFromTheLastRunEqualThoseEvaluatedAgain) {
  auto s = testing::load_model_file(KFW_SOURCE_DIR "/presets/underwater.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["sim.duration"] = 30.0;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  v["sim.seed"] = 5.0;
  auto other = s->simulate(v);
  ASSERT_TRUE(other.ok());
  v["sim.seed"] = 4.0;
  const auto series = [](const RunResult& r) {
    return dynamic_cast<const ModelResult&>(r).derived;
  };
  const auto uncached = [&](const Dataset& data, const ParamValues& values) {
    auto fresh = testing::load_model_file(KFW_SOURCE_DIR "/presets/underwater.json");
    auto r = fresh->run(data, values);
    EXPECT_TRUE(r.ok());
    return series(**r);
  };
  const auto expect_same = [](const std::vector<std::vector<double>>& a,
                              const std::vector<std::vector<double>>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].size(), b[i].size()) << what;
      for (std::size_t k = 0; k < a[i].size(); ++k) {
        const bool both_nan = std::isnan(a[i][k]) && std::isnan(b[i][k]);
        ASSERT_TRUE(both_nan || a[i][k] == b[i][k]) << what << " series " << i << " row " << k;
      }
    }
  };
  auto first = s->run(*d, v);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(series(**first).size(), 6u);
  // The same data, a filter parameter changed: the estimate's series moves, the others are kept.
  v["q_pos"] = 0.5;
  auto second = s->run(*d, v);
  ASSERT_TRUE(second.ok());
  expect_same(series(**second), uncached(*d, v), "same data");
  EXPECT_NE(series(**second).back(), series(**first).back());  // pos_err, the live one
  // Other data of the same size: every series evaluated again.
  auto third = s->run(*other, v);
  ASSERT_TRUE(third.ok());
  expect_same(series(**third), uncached(*other, v), "other data");
  EXPECT_NE(series(**third)[0], series(**second)[0]);
  // One sample changed in a column a series reads (range1): evaluated again.
  Dataset edited = *d;
  auto& r1 = edited.columns[static_cast<std::size_t>(edited.index("range1"))];
  for (double& x : r1) {
    if (std::isfinite(x)) {
      x += 0.25;
      break;
    }
  }
  auto fourth = s->run(edited, v);
  ASSERT_TRUE(fourth.ok());
  expect_same(series(**fourth), uncached(edited, v), "one sample changed");
}

}  // namespace
}  // namespace speed_paths_test
}  // namespace kfw::model
