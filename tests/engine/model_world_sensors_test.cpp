// Issue 27, the world's sensors: named noise sources (white, held, random walk, Gauss–Markov),
// sensor clocks (period, offset, jitter, shared clocks), dropouts and outliers, each drawn from
// its own stream of the random-number specification. Statistics are checked against their
// expected values within 4 standard errors (or stated bounds) over long runs or many seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "core/scenario.h"
#include "model/model_scenario.h"

namespace kfw {
namespace world_sensors_test {
namespace {

using nlohmann::json;

json param(double v, double lo, double hi, const char* unit = "") {
  return {{"value", v}, {"min", lo}, {"max", hi}, {"unit", unit}};
}

// A filter of one constant state read by `z`; the world under test writes z and the columns the
// test reads (its sensors' roles, truth).
json preset(const json& world, double duration = 100, double dt = 0.1) {
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}, {"title", "w"}};
  p["parameters"] = {{"sigma", param(1, 1e-3, 10)},
                     {"sim.duration", param(duration, 0, 1e6, "s")},
                     {"sim.dt", param(dt, 1e-4, 10, "s")}};
  p["model"] = {{"version", 2},
                {"states", {"x"}},
                {"x0", {"0"}},
                {"P0", {"1"}},
                {"process", {{"F", {{"1"}}}, {"Q", {{"0"}}}}},
                {"measurements", {{"z", {{"roles", {"z"}}, {"H", {{"1"}}}, {"R", {"sigma^2"}}}}}},
                {"world", world}};
  return p;
}

// A world of one state at rest whose sensor `z` reads the expression `h` without noise.
json world_reading(const std::string& h, const json& noise) {
  return {
      {"states", {"s"}}, {"x0", {"0"}},
      {"P0", {"0"}},     {"process", {{"F", {{"1"}}}, {"Q", {{"0"}}}}},
      {"noise", noise},  {"measurements", {{"z", {{"roles", {"z"}}, {"h", {h}}, {"R", {"0"}}}}}}};
}

Dataset simulate(const json& p, double seed = 1) {
  auto s = make_model_scenario(p, "w.json");
  EXPECT_TRUE(s.ok()) << s.error();
  if (!s.ok()) return {};
  ParamValues v = (*s)->params().defaults();
  v["sim.seed"] = seed;
  auto d = (*s)->simulate(v);
  EXPECT_TRUE(d.ok()) << d.error();
  return d.ok() ? *d : Dataset{};
}

std::string refusal(const json& p) {
  auto s = make_model_scenario(p, "w.json");
  if (!s.ok()) return s.error();
  auto d = (*s)->simulate((*s)->params().defaults());
  return d.ok() ? "" : d.error();
}

struct Moments {
  double mean = 0, sd = 0, lag1 = 0;
};
Moments moments(const std::vector<double>& v) {
  Moments m;
  const double n = static_cast<double>(v.size());
  for (double x : v)
    m.mean += x / n;
  double var = 0, cov = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    var += (v[i] - m.mean) * (v[i] - m.mean) / n;
    if (i > 0) cov += (v[i] - m.mean) * (v[i - 1] - m.mean) / (n - 1);
  }
  m.sd = std::sqrt(var);
  m.lag1 = cov / var;
  return m;
}

TEST(ModelWorldNoise, WhiteIsANewDrawEveryStep) {
  const Dataset d =
      simulate(preset(world_reading("w", {{"w", {{"kind", "white"}, {"sigma", "2"}}}}), 2000), 1);
  const Moments m = moments(d.col("z"));  // 20001 draws
  EXPECT_NEAR(m.mean, 0.0, 4 * 2 / std::sqrt(20001.0));
  EXPECT_NEAR(m.sd, 2.0, 4 * 2 / std::sqrt(2 * 20001.0));
  EXPECT_NEAR(m.lag1, 0.0, 4 / std::sqrt(20001.0));
}

TEST(ModelWorldNoise, HeldIsRedrawnEveryHoldAndOnceWithoutOne) {
  json noise = {
      {"n_c", {{"kind", "held"}, {"sigma", "3"}, {"hold", "1"}}},
      {"ph", {{"kind", "held"}, {"distribution", "uniform"}, {"min", "0"}, {"max", "2*pi"}}}};
  json w = world_reading("n_c", noise);
  w["measurements"]["p"] = {{"roles", {"p"}}, {"h", {"ph"}}, {"R", {"0"}}};
  const Dataset d = simulate(preset(w, 3000), 1);
  const auto& t = d.col("t");
  const auto& z = d.col("z");
  std::vector<double> windows;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const auto i = static_cast<std::size_t>(std::floor(t[k] / 1.0));  // its window of 1 s
    if (i == windows.size()) windows.push_back(z[k]);
    ASSERT_EQ(z[k], windows[i]) << "row " << k;  // one value per window of 1 s
  }
  ASSERT_EQ(windows.size(), 3001u);
  const Moments m = moments(windows);
  EXPECT_NEAR(m.sd, 3.0, 4 * 3 / std::sqrt(2 * 3001.0));
  EXPECT_NEAR(m.lag1, 0.0, 4 / std::sqrt(3001.0));
  // Without a hold: one draw for the run, uniform on [0, 2π) over seeds.
  double sum = 0;
  for (int seed = 1; seed <= 200; ++seed) {
    const Dataset ds = simulate(preset(w, 1), seed);
    const auto& p = ds.col("p");
    for (double v : p)
      ASSERT_EQ(v, p.front());
    ASSERT_GE(p.front(), 0.0);
    ASSERT_LT(p.front(), 2 * std::numbers::pi);
    sum += p.front() / 200;
  }
  EXPECT_NEAR(sum, std::numbers::pi, 4 * 2 * std::numbers::pi / std::sqrt(12 * 200.0));
}

TEST(ModelWorldNoise, ARandomWalkGrowsAsSigmaSquaredT) {
  // Var b(T) = σ² T: the mean of b(T)² over 400 seeds, relative standard error √(2/400).
  const json w = world_reading("b", {{"b", {{"kind", "random_walk"}, {"sigma", "0.5"}}}});
  double mean_sq = 0;
  for (int seed = 1; seed <= 400; ++seed) {
    const Dataset d = simulate(preset(w, 40), seed);
    EXPECT_EQ(d.col("z").front(), 0.0);
    mean_sq += d.col("z").back() * d.col("z").back() / 400;
  }
  EXPECT_NEAR(mean_sq / (0.25 * 40), 1.0, 4 * std::sqrt(2 / 400.0));
}

TEST(ModelWorldNoise, AGaussMarkovSourceIsStationaryWithItsCorrelationTime) {
  const json w =
      world_reading("g", {{"g", {{"kind", "gauss_markov"}, {"sigma", "1.5"}, {"tau", "0.5"}}}});
  const Dataset d = simulate(preset(w, 4000), 2);
  const Moments m = moments(d.col("z"));  // 40001 steps, lag-1 correlation e^(−0.2)
  const double rho = std::exp(-0.2), n_eff = 40001 * (1 - rho) / (1 + rho);
  EXPECT_NEAR(m.mean, 0.0, 4 * 1.5 / std::sqrt(n_eff));
  EXPECT_NEAR(m.sd, 1.5, 4 * 1.5 / std::sqrt(2 * n_eff));
  EXPECT_NEAR(m.lag1, rho, 4 * (1 - rho * rho) / std::sqrt(40001.0));
}

TEST(ModelWorldNoise, EachSourceHasItsOwnStream) {
  json one = {{"a", {{"kind", "white"}, {"sigma", "1"}}}};
  json two = one;
  two["b"] = {{"kind", "white"}, {"sigma", "1"}};
  const Dataset d1 = simulate(preset(world_reading("a", one), 10), 5);
  const Dataset d2 = simulate(preset(world_reading("a + 0*b", two), 10), 5);
  EXPECT_EQ(d1.col("z"), d2.col("z"));
  const Dataset d3 = simulate(preset(world_reading("a", one), 10), 6);
  EXPECT_NE(d1.col("z"), d3.col("z"));
}

// ---- Clocks

json clocked_world() {
  // A target at constant speed 2 with no process noise, read by two sensors on one jittery
  // clock and by a third on the grid.
  return json::parse(R"J({
    "states": ["p", "v"], "x0": ["0", "2"], "P0": ["0", "0"],
    "process": {"F": [["1", "dt"], ["0", "1"]], "Q": [["0", "0"], ["0", "0"]]},
    "clocks": {"fast": {"period": "0.25", "offset": "0.1", "jitter": "0.01",
                        "resolution": "0.001"}},
    "measurements": {
      "z": {"roles": ["z"], "H": [["1", "0"]], "R": ["0"]},
      "a": {"roles": ["a"], "H": [["1", "0"]], "R": ["0"], "clock": "fast"},
      "b": {"roles": ["b"], "H": [["0", "1"]], "R": ["0"], "clock": "fast"},
      "c": {"roles": ["c"], "H": [["1", "0"]], "R": ["0"],
            "clock": {"period": "0.7", "offset": "0.05"}}
    },
    "truth": {"p": "p_true"}
  })J");
}

TEST(ModelWorldClock, SensorsSampleOnTheirClocksTicks) {
  const Dataset d = simulate(preset(clocked_world(), 200, 0.1), 3);
  const auto &t = d.col("t"), &a = d.col("a"), &b = d.col("b"), &c = d.col("c"), &z = d.col("z");
  std::vector<double> ticks, c_ticks;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (k > 0) {
      ASSERT_LT(t[k - 1], t[k]);
    }
    // A shared clock: a and b sample at the same rows.
    ASSERT_EQ(std::isnan(a[k]), std::isnan(b[k])) << "row " << k;
    if (!std::isnan(a[k])) {
      ticks.push_back(t[k]);
      EXPECT_NEAR(std::round(t[k] * 1000), t[k] * 1000, 1e-6);  // the 1 ms resolution
      EXPECT_NEAR(a[k], 2 * t[k], 1e-9);  // the state at the tick, between grid steps
    }
    if (!std::isnan(c[k])) c_ticks.push_back(t[k]);
    // The grid sensor: every sim.dt.
    const bool on_grid = std::abs(t[k] / 0.1 - std::round(t[k] / 0.1)) < 1e-9;
    EXPECT_EQ(!std::isnan(z[k]), on_grid) << "t " << t[k];
    EXPECT_NEAR(d.col("p_true")[k], 2 * t[k], 1e-9);
  }
  ASSERT_GT(ticks.size(), 700u);
  EXPECT_NEAR(ticks.front(), 0.1, 0.001);
  std::vector<double> dt;
  for (std::size_t i = 1; i < ticks.size(); ++i)
    dt.push_back(ticks[i] - ticks[i - 1]);
  const Moments m = moments(dt);
  EXPECT_NEAR(m.mean, 0.25, 4 * 0.01 / std::sqrt(static_cast<double>(dt.size())));
  EXPECT_NEAR(m.sd, 0.01, 0.0015);  // jitter 10 ms, rounded to 1 ms
  // A clock without jitter: its period exactly, from its offset.
  ASSERT_EQ(c_ticks.size(), static_cast<std::size_t>(std::floor((200 - 0.05) / 0.7)) + 1);
  for (std::size_t i = 0; i < c_ticks.size(); ++i)
    EXPECT_NEAR(c_ticks[i], 0.05 + 0.7 * static_cast<double>(i), 1e-9);
}

TEST(ModelWorldClock, ClockErrorsNameTheKey) {
  json w = clocked_world();
  w["measurements"]["a"]["clock"] = "fsat";
  EXPECT_NE(refusal(preset(w)).find("model.world.measurements.a.clock: unknown clock 'fsat' "
                                    "(did you mean 'fast'?)"),
            std::string::npos)
      << refusal(preset(w));
  w = clocked_world();
  w["measurements"]["a"]["every"] = 2;
  EXPECT_NE(refusal(preset(w)).find("model.world.measurements.a.every: a sensor with a clock"),
            std::string::npos)
      << refusal(preset(w));
  w = clocked_world();
  w["clocks"]["fast"]["period"] = "0";
  EXPECT_NE(refusal(preset(w)).find("model.world.clocks.fast.period: expected > 0 s"),
            std::string::npos)
      << refusal(preset(w));
  // Fewer than two ticks in the run: no data a filter could run on.
  w = clocked_world();
  for (const char* s : {"z", "a", "b", "c"})
    w["measurements"][s]["clock"] = "fast";
  w["clocks"]["fast"]["period"] = "500";
  EXPECT_NE(refusal(preset(w)).find("model.world.clocks: the sensors' clocks tick 1 time(s)"),
            std::string::npos)
      << refusal(preset(w));
  // A filter's channel has no clock.
  json p = preset(clocked_world());
  p["model"]["measurements"]["z"]["clock"] = "fast";
  EXPECT_NE(refusal(p).find("w.json: model.measurements.z.clock: a sensor's key"),
            std::string::npos)
      << refusal(p);
}

// ---- Dropouts and outliers

json sensing_world() {
  return json::parse(R"J({
    "states": ["s"], "x0": ["0"], "P0": ["0"],
    "process": {"F": [["1"]], "Q": [["0"]]},
    "measurements": {
      "z": {"roles": ["z"], "H": [["1"]], "R": ["1"]},
      "r1": {"roles": ["r1"], "H": [["1"]], "R": ["1"], "dropout": "0.3",
             "outliers": {"count": "50", "size": "20", "group": "ranges", "column": "out1"}},
      "r2": {"roles": ["r2"], "H": [["1"]], "R": ["1"],
             "outliers": {"count": "50", "size": "20", "group": "ranges", "column": "out2"}}
    }
  })J");
}

TEST(ModelWorldSensor, DropoutsLoseSamplesAtTheirRate) {
  const Dataset d = simulate(preset(sensing_world(), 1000), 1);
  const auto& r1 = d.col("r1");
  double lost = 0;
  for (double v : r1)
    lost += std::isnan(v) ? 1 : 0;
  const double n = static_cast<double>(r1.size());
  EXPECT_NEAR(lost / n, 0.3, 4 * std::sqrt(0.3 * 0.7 / n));
  // The other sensors' draws are their own: z is the same with no dropout declared.
  json w = sensing_world();
  w["measurements"]["r1"].erase("dropout");
  const Dataset d0 = simulate(preset(w, 1000), 1);
  EXPECT_EQ(d0.col("z"), d.col("z"));
  for (std::size_t k = 0; k < r1.size(); ++k) {
    if (!std::isnan(r1[k]) && d.col("out1")[k] == 0.0 && d0.col("out1")[k] == 0.0) {
      ASSERT_EQ(r1[k], d0.col("r1")[k]);
    }
  }
}

TEST(ModelWorldSensor, AGroupOfSensorsGetsItsCountOfOutliers) {
  for (int seed = 1; seed <= 5; ++seed) {
    const Dataset d = simulate(preset(sensing_world(), 100), seed);
    int outliers = 0;
    for (const char* s : {"1", "2"}) {
      const auto& r = d.col(std::string("r") + s);
      const auto& o = d.col(std::string("out") + s);
      for (std::size_t k = 0; k < r.size(); ++k) {
        ASSERT_EQ(std::isnan(r[k]), std::isnan(o[k])) << "a sample has an outlier entry";
        if (std::isnan(o[k]) || o[k] == 0.0) continue;
        ASSERT_EQ(std::abs(o[k]), 20.0);
        EXPECT_GT(std::abs(r[k]), 8.0);  // 20 against unit noise
        ++outliers;
      }
    }
    EXPECT_EQ(outliers, 50) << "seed " << seed;  // drawn once for the group of both
  }
  // A rate: each sample with that probability.
  json w = sensing_world();
  w["measurements"]["r2"]["outliers"] = {{"rate", "0.1"}, {"size", "5"}, {"column", "out2"}};
  const Dataset d = simulate(preset(w, 1000), 1);
  double hits = 0;
  for (double o : d.col("out2"))
    hits += o != 0.0 ? 1 : 0;
  const double n = static_cast<double>(d.rows());
  EXPECT_NEAR(hits / n, 0.1, 4 * std::sqrt(0.1 * 0.9 / n));
}

TEST(ModelWorldSensor, SensorKeysAreChecked) {
  json w = sensing_world();
  w["measurements"]["r1"]["dropout"] = "1.5";
  EXPECT_NE(refusal(preset(w)).find("dropout: expected a probability in [0, 1]"), std::string::npos)
      << refusal(preset(w));
  w = sensing_world();
  w["measurements"]["r1"]["outliers"] = {{"size", "1"}};
  EXPECT_NE(
      refusal(preset(w)).find("model.world.measurements.r1.outliers: declare exactly one of count"),
      std::string::npos)
      << refusal(preset(w));
  w = sensing_world();
  w["measurements"]["r2"]["outliers"]["count"] = "7";
  EXPECT_NE(refusal(preset(w)).find("the group 'ranges'"), std::string::npos) << refusal(preset(w));
  w = sensing_world();
  w["noise"] = {{"q", {{"kind", "pink"}, {"sigma", "1"}}}};
  EXPECT_NE(refusal(preset(w)).find("model.world.noise.q.kind: 'pink' is not a kind of noise"),
            std::string::npos)
      << refusal(preset(w));
  json p = preset(sensing_world());
  p["model"]["noise"] = json::object();
  EXPECT_NE(refusal(p).find("model.noise: a key of the world block"), std::string::npos)
      << refusal(p);
}

// A world's truth may be a sub-expression: a quantity that is not one of its states.
TEST(ModelWorldSensor, ATruthColumnMayBeASubExpression) {
  json w = world_reading("s", json::object());
  w["expressions"] = {{"sway", "3*sin(0.5*t)"}};
  w["truth"] = {{"sway", "sway_true"}};
  const Dataset d = simulate(preset(w, 10), 1);
  const auto& t = d.col("t");
  for (std::size_t k = 0; k < t.size(); ++k)
    EXPECT_DOUBLE_EQ(d.col("sway_true")[k], 3 * std::sin(0.5 * t[k]));
}

// The README's example of these keys loads and simulates as written.
TEST(ModelWorldSensor, TheReadmeExampleRuns) {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/README.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string readme = ss.str();
  const auto at = readme.find("**Rows and time.**");
  ASSERT_NE(at, std::string::npos);
  const auto open = readme.find("```json\n", at) + 8, close = readme.find("```", open);
  const json w = json::parse("{" + readme.substr(open, close - open) + "}").at("world");
  json p = preset(w, 600);
  p["model"]["measurements"] = {{"r1", {{"roles", {"r1"}}, {"H", {{"1"}}}, {"R", {"sigma^2"}}}}};
  for (const char* k : {"sigma_c", "t_gap", "q", "sigma_r", "n_out"})
    p["parameters"][k] = param(1, 0, 100);
  p["parameters"]["n_out"]["value"] = 20;
  p["parameters"]["t_gap"]["value"] = 10;
  const Dataset d = simulate(p, 1);
  int outliers = 0;
  for (const char* c : {"out1", "out2"}) {
    for (double o : d.col(c))
      outliers += !std::isnan(o) && o != 0.0;
  }
  EXPECT_EQ(outliers, 20);
  EXPECT_GT(d.rows(), 6001u);  // the grid of 0.1 s (speed) and the jittered ticks between
}

}  // namespace
}  // namespace world_sensors_test
}  // namespace kfw
