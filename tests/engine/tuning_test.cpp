#include "experiment/tuning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "document/preset.h"
#include "document/workspace.h"

namespace kfw {
namespace {

// Seed 000's model file; its table's defaults are the file's values.
std::shared_ptr<const Scenario> heli() {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  EXPECT_TRUE(p.ok()) << p.error();
  return p.ok() ? p->instance : nullptr;
}

TuneObjective objective(const Scenario& s, const std::string& name) {
  auto o = make_objective(s, name);
  EXPECT_TRUE(o.ok()) << o.error();
  return *o;
}

SearchParam noise(const std::string& key, double lo, double hi) {
  return {key, lo, hi, true, "noise"};
}

// From a poor start, the search reaches the RMSE of the simulator's true noise tuning.
TEST(Tuning, FindsTheTrueNoiseTuningOnSimulatedData) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 60;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  const double truth_rmse = (*s->run(*d, v))->metrics.at("rmse");
  auto start = v;
  start["Q"] = 1.0;
  start["R"] = 100.0;
  const double start_rmse = (*s->run(*d, start))->metrics.at("rmse");
  auto r = tune(*s, {{"sim", &*d}}, start, {{"Q", 1e-3, 1e5, true}, {"R", 1e-3, 1e5, true}},
                objective(*s, "rmse"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_GT(start_rmse, 1.3 * truth_rmse);
  EXPECT_LT(r->value, 1.01 * truth_rmse);
  EXPECT_LE(r->evaluations, 420);
}

// Objectives follow the declared direction: nis_mean is driven to its target 1.
TEST(Tuning, TargetObjectiveIsDrivenToItsTarget) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 30;
  auto d = s->simulate(v);
  auto start = v;
  start["R"] = 50.0;  // NIS far below 1
  auto r = tune(*s, {{"sim", &*d}}, start, {{"R", 1e-3, 1e5, true}}, objective(*s, "nis_mean"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_NEAR(r->value, 1.0, 0.01);
  EXPECT_FALSE(make_objective(*s, "rmes").ok());
  EXPECT_EQ(make_objective(*s, "nis")->spec.key, "nis_mean");
}

// A 2-state filter's RMSE depends on Q/R only: the check says the scale is undetermined, and the
// tuner sets it by consistency (NIS mean / dof = 1).
TEST(Tuning, RmseCannotTellTheNoiseScale) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 60;
  auto d = s->simulate(v);
  auto r = tune(*s, {{"sim", &*d}}, v, {noise("Q", 1e-3, 1e5), noise("R", 1e-3, 1e5)},
                objective(*s, "rmse"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->scales.size(), 1u);
  EXPECT_FALSE(r->scales[0].determined) << r->scales[0].change;
  EXPECT_TRUE(r->scales[0].by_consistency);
  EXPECT_NEAR(r->metrics.at("nis_mean"), 1.0, 0.02);
  // NLL does depend on the scale.
  auto n = tune(*s, {{"sim", &*d}}, v, {noise("Q", 1e-3, 1e5), noise("R", 1e-3, 1e5)},
                objective(*s, "nll"), {.budget = 60});
  ASSERT_TRUE(n.ok()) << n.error();
  EXPECT_TRUE(n->scales[0].determined);
}

// Issue 14 acceptance: simulations made with Q = 67.24, R = 1.96 (bias walk off), seeds 1–10;
// rmse+nis recovers Q and R within 20 % and NIS mean within 10 % of 1 on at least 8 seeds.
TEST(Tuning, RmseNisRecoversTheSimulatorsNoise) {
  auto s = heli();
  int good = 0;
  std::string log;
  for (int seed = 1; seed <= 10; ++seed) {
    auto v = s->params().defaults();
    v["sim.seed"] = seed;
    v["sim.bias_walk"] = 0.0;
    auto d = s->simulate(v);
    ASSERT_TRUE(d.ok());
    auto start = v;
    start["Q"] = 1.0;
    start["R"] = 100.0;
    auto r = tune(*s, {{"sim", &*d}}, start, {noise("Q", 1e-3, 1e5), noise("R", 1e-3, 1e5)},
                  objective(*s, kRmseNis));
    ASSERT_TRUE(r.ok()) << r.error();
    const double q = r->best.at("Q") / 67.24, rr = r->best.at("R") / 1.96;
    const double nis = r->metrics.at("nis_mean");
    const bool ok = std::abs(q - 1) < 0.2 && std::abs(rr - 1) < 0.2 && std::abs(nis - 1) < 0.1;
    good += ok ? 1 : 0;
    log += "seed " + std::to_string(seed) + ": Q/Q0 " + std::to_string(q) + " R/R0 " +
           std::to_string(rr) + " NIS " + std::to_string(nis) + "\n";
  }
  EXPECT_GE(good, 8) << log;
}

// The optimum on a bound is reported.
TEST(Tuning, OptimumOnABoundIsReported) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 30;
  auto d = s->simulate(v);
  // R's true value 1.96 lies above this box: the best R sits on its upper bound.
  auto r = tune(*s, {{"sim", &*d}}, v, {{"Q", 1, 1e4, true}, {"R", 0.01, 0.1, true}},
                objective(*s, "rmse"), {.budget = 80});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->at_bound.size(), 1u);
  EXPECT_EQ(r->at_bound[0], "R");
}

// Several logs: two copies of a log give the single-log tuning exactly; a different log is
// reported separately and the worst aggregate ranks by the larger RMSE.
TEST(Tuning, ManyLogsAggregate) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 30;
  auto d1 = s->simulate(v);
  v["sim.seed"] = 2;
  v["sim.sigma_angle"] = 3.0;
  auto d2 = s->simulate(v);
  const std::vector<SearchParam> p = {{"Q", 1e-2, 1e4, true}, {"gamma", 0, 0.05, false}};
  const TuneOptions opt{.budget = 120};
  auto one = tune(*s, {{"a", &*d1}}, v, p, objective(*s, "rmse"), opt);
  auto two = tune(*s, {{"a", &*d1}, {"a again", &*d1}}, v, p, objective(*s, "rmse"), opt);
  ASSERT_TRUE(one.ok() && two.ok());
  EXPECT_EQ(one->best, two->best);
  EXPECT_EQ(one->value, two->value);
  ASSERT_EQ(two->logs.size(), 2u);
  auto mixed = tune(*s, {{"a", &*d1}, {"b", &*d2}}, v, p, objective(*s, "rmse"),
                    {.budget = 120, .aggregate = Aggregate::kWorst});
  ASSERT_TRUE(mixed.ok());
  ASSERT_EQ(mixed->logs.size(), 2u);
  EXPECT_EQ(mixed->logs[1].name, "b");
  EXPECT_DOUBLE_EQ(mixed->value, std::max(mixed->logs[0].value, mixed->logs[1].value));
  EXPECT_GT(mixed->logs[1].value, mixed->logs[0].value);  // the noisier sensor
}

TEST(Tuning, MethodsAndBadInput) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 20;
  auto d = s->simulate(v);
  for (auto m : {TuneMethod::kSbplx, TuneMethod::kDirect, TuneMethod::kCrs}) {
    auto r = tune(*s, {{"sim", &*d}}, v, {{"Q", 1, 1e4, true}, {"gamma", 0, 0.05, false}},
                  objective(*s, "rmse"), {.method = m, .budget = 80});
    ASSERT_TRUE(r.ok()) << tune_method_name(m) << ": " << r.error();
    EXPECT_LE(r->evaluations, 90);
  }
  EXPECT_FALSE(parse_tune_method("bobyq").ok());
  EXPECT_NE(parse_tune_method("bobyq").error().find("did you mean 'bobyqa'"), std::string::npos);
  const auto obj = objective(*s, "rmse");
  EXPECT_FALSE(tune(*s, {{"sim", &*d}}, v, {}, obj).ok());
  EXPECT_FALSE(tune(*s, {{"sim", &*d}}, v, {{"zz", 0, 1, false}}, obj).ok());
  EXPECT_FALSE(tune(*s, {{"sim", &*d}}, v, {{"Q", 0, 1, true}}, obj).ok());
}

// Seed 000 Fig. 8: RMS error versus γ has an interior minimum when the bias drifts.
TEST(Sweep, GammaHasAnInteriorMinimum) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.bias_walk"] = 0.5;
  v["sim.duration"] = 300;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  auto axis = parse_sweep_axis(s->params(), "gamma=0:0.05:11");
  ASSERT_TRUE(axis.ok()) << axis.error();
  auto r = sweep(*s, *d, v, {*axis}, 2);
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->points.size(), 11u);
  std::size_t best = 0;
  for (std::size_t i = 0; i < 11; ++i) {
    if (r->metrics[i].at("rmse") < r->metrics[best].at("rmse")) best = i;
  }
  EXPECT_GT(best, 0u);
  EXPECT_LT(best, 10u);
}

// Shards partition the grid: together they hold every point once, with the same values.
TEST(Sweep, ShardsPartitionTheGrid) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 10;
  auto d = s->simulate(v);
  const std::vector<SweepAxis> axes = {{"Q", 1, 100, 5, true}, {"R", 0.5, 5, 3, false}};
  auto all = sweep(*s, *d, v, axes, 2);
  ASSERT_TRUE(all.ok());
  std::size_t seen = 0;
  for (std::size_t i = 1; i <= 4; ++i) {
    auto part = sweep(*s, *d, v, axes, 1, nullptr, Shard{i, 4});
    ASSERT_TRUE(part.ok());
    EXPECT_EQ(part->points.size(), shard_size(15, Shard{i, 4}));
    for (std::size_t k = 0; k < part->points.size(); ++k) {
      const std::size_t idx = part->indices[k];
      EXPECT_EQ(idx % 4, i - 1);
      EXPECT_EQ(part->points[k], all->points[idx]);
      EXPECT_EQ(part->metrics[k], all->metrics[idx]);
      ++seen;
    }
  }
  EXPECT_EQ(seen, 15u);
  EXPECT_EQ(grid_size(axes, 14), std::nullopt);
}

TEST(Sweep, BadAxesAreErrors) {
  auto s = heli();
  EXPECT_FALSE(parse_sweep_axis(s->params(), "nope=0:1:3").ok());
  EXPECT_FALSE(parse_sweep_axis(s->params(), "Q=1:2").ok());
  EXPECT_FALSE(parse_sweep_axis(s->params(), "Q=1:2:0").ok());
  EXPECT_FALSE(parse_sweep_axis(s->params(), "Q=-1:2:3").ok());
}

// Issue 6/14 acceptance on the real log: the tuner keeps or beats 1.563° (the Nelder–Mead
// result) and a dense grid's best; the truth-free NLL tuning trusts the accelerometer far too
// much, and the whiteness test flags it.
TEST(Tuning, RealLogTuneBeatsTheDenseGridAndNllIsFlagged) {
  const std::string path =
      std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not present";
  auto ws = open_workspace(std::string(KFW_SOURCE_DIR) + "/presets/broad_imu.json", {}, {});
  ASSERT_TRUE(ws.ok()) << ws.error();
  auto d = load_dataset(*ws);
  ASSERT_TRUE(d.ok());
  SweepAxis q{"Q", 1, 1e5, 9, true}, r{"R", 1e1, 1e6, 9, true}, g{"gamma", 0, 0.01, 6, false};
  auto grid = sweep(*ws->scenario, *d, ws->values, {q, r, g}, 2);
  ASSERT_TRUE(grid.ok());
  double grid_best = 1e9;
  for (const auto& m : grid->metrics)
    grid_best = std::min(grid_best, m.at("rmse"));
  std::vector<SearchParam> params;
  for (const char* k : {"Q", "R", "gamma"})
    params.push_back(*search_param(ws->preset, k));
  auto tuned =
      tune(*ws->scenario, {{path, &*d}}, ws->values, params, objective(*ws->scenario, "rmse"));
  ASSERT_TRUE(tuned.ok()) << tuned.error();
  EXPECT_LT(tuned->value, grid_best);
  EXPECT_LT(tuned->value, 1.5635);  // 1.563° as the README gave it (three decimals)

  auto nll = tune(*ws->scenario, {{path, &*d}}, ws->values,
                  {{"Q", 1, 1e5, true}, {"R", 1e-6, 1e6, true}, {"gamma", 0, 0.01, false}},
                  objective(*ws->scenario, "nll"));
  ASSERT_TRUE(nll.ok());
  EXPECT_GT(nll->metrics.at("rmse"), 3.0 * tuned->value);
  EXPECT_LT(nll->metrics.at("whiteness_p"), 0.01);
  EXPECT_FALSE(nll->at_bound.empty());  // R runs to its lower bound: said so
}

}  // namespace
}  // namespace kfw
