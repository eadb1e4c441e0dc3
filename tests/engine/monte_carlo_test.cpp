// Monte Carlo runs: per-seed metrics equal single runs whatever the threads, shards merge into
// the unsharded result (relative 1e-12, also through the part files), stopped seeds are listed
// and left out, undefined metrics are aggregated where defined, and a matched linear model
// (cv1d, initial state drawn from the prior) passes the ANEES/ANIS test over 50 runs while a
// mismatched one fails it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/statistics.h"
#include "document/preset.h"
#include "experiment/monte_carlo.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

const std::string kModels = KFW_SOURCE_DIR "/presets/models/";

std::shared_ptr<const Scenario> cv1d(bool x0_from_prior) {
  std::ifstream in(kModels + "cv1d.json");
  auto s = make_model_scenario(nlohmann::json::parse(in), kModels + "cv1d.json");
  EXPECT_TRUE(s.ok()) << s.error();
  std::shared_ptr<const Scenario> sc = std::move(*s);
  return x0_from_prior ? sc->with_x0_from_prior() : sc;
}

std::vector<long long> seeds(long long lo, long long hi) {
  std::vector<long long> v;
  for (long long s = lo; s <= hi; ++s)
    v.push_back(s);
  return v;
}

void expect_rel(double a, double b, const std::string& what) {
  if (std::isnan(a) && std::isnan(b)) return;
  EXPECT_LE(std::abs(a - b), 1e-12 * std::max(std::abs(a), std::abs(b)) + 1e-300)
      << what << ": " << a << " vs " << b;
}

void expect_same_summary(const MonteCarloSummary& a, const MonteCarloSummary& b) {
  EXPECT_EQ(a.seeds, b.seeds);
  EXPECT_EQ(a.completed, b.completed);
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  for (const auto& [k, m] : a.metrics) {
    const MetricSummary& o = b.metrics.at(k);
    EXPECT_EQ(m.n, o.n) << k;
    expect_rel(m.mean, o.mean, k + " mean");
    expect_rel(m.sd, o.sd, k + " sd");
    expect_rel(m.min, o.min, k + " min");
    expect_rel(m.max, o.max, k + " max");
  }
  ASSERT_EQ(a.nees.has_value(), b.nees.has_value());
  ASSERT_EQ(a.nis.size(), b.nis.size());
  auto same = [](const ConsistencySummary& x, const ConsistencySummary& y) {
    ASSERT_EQ(x.average.size(), y.average.size());
    for (std::size_t k = 0; k < x.average.size(); ++k)
      expect_rel(x.average[k], y.average[k], x.name + " step " + std::to_string(k));
    expect_rel(x.time_average, y.time_average, x.name + " time average");
    EXPECT_EQ(x.inside, y.inside);
    EXPECT_EQ(x.runs, y.runs);
  };
  if (a.nees) same(*a.nees, *b.nees);
  for (std::size_t i = 0; i < a.nis.size(); ++i)
    same(a.nis[i], b.nis[i]);
}

TEST(MonteCarlo, PerSeedMetricsEqualSingleRunsWhateverTheThreads) {
  auto s = cv1d(false);
  ParamValues v = s->params().defaults();
  v["sim.duration"] = 5.0;
  const auto set = seeds(1, 6);
  MonteCarloOptions one, two;
  one.threads = 1;
  two.threads = 2;
  auto a = run_monte_carlo(*s, v, {6, 3, 1, 2, 5, 4}, {}, one);
  auto b = run_monte_carlo(*s, v, set, {}, two);
  ASSERT_TRUE(a.ok()) << a.error();
  ASSERT_TRUE(b.ok()) << b.error();
  ASSERT_EQ(a->runs.size(), 6u);
  for (std::size_t i = 0; i < set.size(); ++i) {
    EXPECT_EQ(a->runs[i].seed, set[i]);
    EXPECT_EQ(a->runs[i].metrics, b->runs[i].metrics);
    ParamValues vi = v;
    vi["sim.seed"] = static_cast<double>(set[i]);
    auto d = s->simulate(vi);
    ASSERT_TRUE(d.ok());
    auto r = s->run(*d, vi);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(a->runs[i].metrics, (*r)->metrics) << "seed " << set[i];
  }
  expect_same_summary(summarize_monte_carlo(*a), summarize_monte_carlo(*b));
}

TEST(MonteCarlo, MergedShardsEqualTheUnshardedRunThroughTheirFiles) {
  auto s = cv1d(true);
  ParamValues v = s->params().defaults();
  v["sim.duration"] = 4.0;
  const auto set = seeds(1, 11);
  auto whole = run_monte_carlo(*s, v, set);
  ASSERT_TRUE(whole.ok()) << whole.error();
  std::vector<MonteCarloPart> parts;
  for (std::size_t i : {3u, 1u, 2u}) {  // any order
    auto p = run_monte_carlo(*s, v, set, Shard{i, 3});
    ASSERT_TRUE(p.ok()) << p.error();
    const std::string text = part_to_json(*p).dump(1);
    auto back = part_from_json(nlohmann::json::parse(text), "part" + std::to_string(i));
    ASSERT_TRUE(back.ok()) << back.error();
    parts.push_back(std::move(*back));
  }
  EXPECT_EQ(parts[1].runs.size(), 4u);  // shard 1/3: seeds 1, 4, 7, 10
  auto merged = merge_montecarlo_parts(parts);
  ASSERT_TRUE(merged.ok()) << merged.error();
  const MonteCarloSummary a = summarize_monte_carlo(*whole), b = summarize_monte_carlo(*merged);
  ASSERT_TRUE(a.nees.has_value());
  EXPECT_EQ(a.nees->runs, 11u);
  expect_same_summary(a, b);

  // A shard given twice or missing, or a part of another seed set, is refused.
  auto twice = merge_montecarlo_parts({parts[0], parts[0], parts[1]}, {"a.json", "b.json", "c"});
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.error().find("b.json: shard 3/3 is given twice"), std::string::npos)
      << twice.error();
  auto missing = merge_montecarlo_parts({parts[0], parts[1]});
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("shard 2/3 is missing"), std::string::npos) << missing.error();
  MonteCarloPart other = parts[2];
  other.seeds.push_back(99);
  EXPECT_FALSE(merge_montecarlo_parts({parts[0], parts[1], other}).ok());
}

TEST(MonteCarlo, BoundsForFiftyRunsAreTheChiSquareQuantiles) {
  // Bar-Shalom et al. 2001, sec. 5.4.2: N·ANEES ~ χ²(N n). The issue's figures for N = 50.
  EXPECT_NEAR(chi2_quantile(0.025, 100) / 50, 1.484, 5e-4);
  EXPECT_NEAR(chi2_quantile(0.975, 100) / 50, 2.591, 5e-4);
  EXPECT_NEAR(chi2_quantile(0.025, 50) / 50, 0.647, 5e-4);
  EXPECT_NEAR(chi2_quantile(0.975, 50) / 50, 1.428, 5e-4);
  // Large degrees of freedom (10 000 runs of 3 states) stay finite and near the normal limit.
  const double k = 30000;
  EXPECT_NEAR(chi2_quantile(0.975, k), k + 1.959964 * std::sqrt(2 * k), 2.0);
}

TEST(MonteCarlo, MatchedLinearModelPassesTheConsistencyTestAndAMismatchedOneFails) {
  auto s = cv1d(true);
  ParamValues v = s->params().defaults();
  v["sim.duration"] = 10.0;  // 101 steps
  auto part = run_monte_carlo(*s, v, seeds(1, 50));
  ASSERT_TRUE(part.ok()) << part.error();
  const MonteCarloSummary m = summarize_monte_carlo(*part);
  ASSERT_TRUE(m.nees.has_value());
  ASSERT_EQ(m.nis.size(), 1u);
  EXPECT_EQ(m.nees->runs, 50u);
  EXPECT_EQ(m.nees->dof, 2.0);
  EXPECT_GE(m.nees->time_average, m.nees->lo);
  EXPECT_LE(m.nees->time_average, m.nees->hi);
  EXPECT_GE(m.nees->inside, 0.90);
  EXPECT_GE(m.nis[0].time_average, m.nis[0].lo);
  EXPECT_LE(m.nis[0].time_average, m.nis[0].hi);
  EXPECT_GE(m.nis[0].inside, 0.90);
  // The error band over the seeds matches the filter's σ (x, the primary state).
  ASSERT_TRUE(m.error.has_value());
  EXPECT_EQ(m.error->state, "x");
  const std::size_t last = m.error->sd.size() - 1;
  EXPECT_NEAR(m.error->sd[last] / m.error->filter_sigma[last], 1.0, 0.3);
  EXPECT_LT(std::abs(m.error->mean[last]), 3.0 * m.error->filter_sigma[last] / std::sqrt(50.0));

  // The filter believes σ_a = 0.5 while the truth moves with σ_a = 3: ANEES far above its bounds.
  StepSums nees{"nees", "NEES", 2.0, {}, {}, {}};
  for (long long seed = 1; seed <= 50; ++seed) {
    ParamValues sim = v;
    sim["sim.seed"] = static_cast<double>(seed);
    sim["sigma_a"] = 3.0;
    auto d = s->simulate(sim);
    ASSERT_TRUE(d.ok());
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok());
    nees.add((*r)->nees_series().nees);
  }
  MonteCarloPart bad = *part;
  bad.nees = nees;
  const MonteCarloSummary b = summarize_monte_carlo(bad);
  EXPECT_GT(b.nees->time_average, b.nees->hi);
  EXPECT_LT(b.nees->inside, 0.5);
}

// The issue's acceptance: helicopter, matched (bias walk off, x0 from the prior), 50 seeds.
TEST(MonteCarlo, HelicopterMatchedPassesAndTheBiasWalkFails) {
  auto p = parse_preset(
      R"({"format": "kfw-preset", "version": 2, "scenario": "helicopter",
          "sim": {"x0_from_prior": true}})",
      "h.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  v["sim.duration"] = 20.0;  // 1 001 steps
  v["sim.bias_walk"] = 0.0;
  v["gamma"] = 0.0;
  auto part = run_monte_carlo(*p->instance, v, seeds(1, 50));
  ASSERT_TRUE(part.ok()) << part.error();
  const MonteCarloSummary m = summarize_monte_carlo(*part);
  ASSERT_TRUE(m.nees.has_value());
  ASSERT_EQ(m.nis.size(), 1u);
  EXPECT_EQ(m.nees->dof, 2.0);
  EXPECT_NEAR(m.nees->lo, 1.484, 5e-4);
  EXPECT_NEAR(m.nees->hi, 2.591, 5e-4);
  EXPECT_NEAR(m.nis[0].lo, 0.647, 5e-4);
  EXPECT_NEAR(m.nis[0].hi, 1.428, 5e-4);
  EXPECT_GE(m.nees->time_average, m.nees->lo);
  EXPECT_LE(m.nees->time_average, m.nees->hi);
  EXPECT_GE(m.nees->inside, 0.90);
  EXPECT_GE(m.nis[0].time_average, m.nis[0].lo);
  EXPECT_LE(m.nis[0].time_average, m.nis[0].hi);
  EXPECT_GE(m.nis[0].inside, 0.90);

  v["sim.bias_walk"] = 0.5;  // the truth's bias wanders, the filter's does not
  auto walk = run_monte_carlo(*p->instance, v, seeds(1, 50));
  ASSERT_TRUE(walk.ok()) << walk.error();
  const MonteCarloSummary w = summarize_monte_carlo(*walk);
  EXPECT_GT(w.nees->time_average, w.nees->hi);
  EXPECT_LT(w.nees->inside, 0.5);
}

// A scenario whose runs stop for every third seed and whose metric `even` exists for even seeds.
struct FakeResult : RunResult {
  Dataset table() const override { return {}; }
};

class FlakyScenario : public Scenario {
 public:
  std::string name() const override { return "flaky"; }
  std::string title() const override { return "flaky"; }
  const ParamTable& params() const override { return table_; }
  std::vector<ColumnSpec> columns() const override { return {}; }
  Expected<Dataset> simulate(const ParamValues& p) const override {
    Dataset d;
    d.add("t", 3);
    d.add("seed", 3);
    for (std::size_t k = 0; k < 3; ++k) {
      d.columns[0][k] = static_cast<double>(k);
      d.columns[1][k] = p.at("sim.seed");
    }
    return d;
  }

 protected:
  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues&,
                                                const RunControl&) const override {
    const auto seed = static_cast<long long>(d.col("seed")[0]);
    if (seed % 3 == 0) return failure("step 1: S is not positive definite");
    auto r = std::make_shared<FakeResult>();
    r->t = d.col("t");
    r->metrics["value"] = static_cast<double>(seed);
    if (seed % 2 == 0) {
      r->metrics["even"] = static_cast<double>(seed);
    } else {
      r->undefined["even"] = "odd seed";
    }
    return std::shared_ptr<RunResult>(r);
  }

 private:
  ParamTable table_{std::vector<ParamSpec>{{"sim.seed", "seed", "", 0, 100, 1, Scale::kInteger}}};
};

TEST(MonteCarlo, StoppedSeedsAreListedAndUndefinedMetricsCountedWhereDefined) {
  FlakyScenario s;
  auto part = run_monte_carlo(s, s.params().defaults(), seeds(1, 10));
  ASSERT_TRUE(part.ok()) << part.error();
  const MonteCarloSummary m = summarize_monte_carlo(*part);
  EXPECT_EQ(m.seeds, 10u);
  EXPECT_EQ(m.completed, 7u);
  ASSERT_EQ(m.stopped.size(), 3u);
  EXPECT_EQ(m.stopped[0].seed, 3);
  EXPECT_NE(m.stopped[2].error.find("not positive definite"), std::string::npos);
  // value over 1 2 4 5 7 8 10; even over 2 4 8 10.
  EXPECT_EQ(m.metrics.at("value").n, 7u);
  EXPECT_DOUBLE_EQ(m.metrics.at("value").mean, 37.0 / 7.0);
  EXPECT_EQ(m.metrics.at("even").n, 4u);
  EXPECT_DOUBLE_EQ(m.metrics.at("even").mean, 6.0);
  EXPECT_DOUBLE_EQ(m.metrics.at("even").min, 2.0);
  EXPECT_DOUBLE_EQ(m.metrics.at("even").max, 10.0);
  EXPECT_NEAR(m.metrics.at("even").sd, std::sqrt((16 + 4 + 4 + 16) / 3.0), 1e-12);
  EXPECT_EQ(m.undefined.count("even"), 0u);

  // A seed outside sim.seed's range is refused before any run.
  auto out = run_monte_carlo(s, s.params().defaults(), {1, 101});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.exit_code(), kExitInvalid);
  EXPECT_NE(out.error().find("--seeds"), std::string::npos) << out.error();
}

TEST(MonteCarlo, X0FromPriorIsRefusedWhereTheScenarioCannotDrawIt) {  // radome: not offered
  auto p = parse_preset(
      R"({"format": "kfw-preset", "version": 2, "scenario": "radome", "sim": {"x0_from_prior": true}})",
      "r.json");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("r.json: sim.x0_from_prior"), std::string::npos) << p.error();
}

}  // namespace
}  // namespace kfw
