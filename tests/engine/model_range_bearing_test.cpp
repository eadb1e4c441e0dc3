// presets/models/range_bearing.json: a nonlinear 2-D channel whose bearing crosses ±π. Over 50
// matched simulations the EKF and the UKF are consistent: the 50-run average NEES (4 dof) and
// NIS (2 dof) per step lie inside their 95 % χ² bounds at ≥ 90 % of the steps, and their time
// averages inside those bounds too (Bar-Shalom, Li, Kirubarajan 2001, sec. 5.4.2).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/scenario.h"
#include "core/statistics.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

const std::string kPath = KFW_SOURCE_DIR "/presets/models/range_bearing.json";

nlohmann::json preset_json() {
  std::ifstream in(kPath);
  return nlohmann::json::parse(in);
}

std::unique_ptr<Scenario> load(const nlohmann::json& j) {
  auto s = make_model_scenario(j, kPath);
  EXPECT_TRUE(s.ok()) << s.error();
  return s.ok() ? std::move(*s) : nullptr;
}

struct Averages {
  std::vector<double> nees, nis;  // per step, averaged over the runs
};

void check_consistency(const std::string& filter) {
  SCOPED_TRACE(filter);
  auto s = load(preset_json());
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  ASSERT_TRUE(s->params().apply_assignment("filter=" + filter, v).ok());
  constexpr int kRuns = 50;
  Averages avg;
  for (int seed = 1; seed <= kRuns; ++seed) {
    v["sim.seed"] = seed;
    auto d = s->simulate(v);
    ASSERT_TRUE(d.ok()) << d.error();
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& m = dynamic_cast<const model::ModelResult&>(**r);
    ASSERT_EQ(m.nees_dof, 4.0);
    if (avg.nees.empty()) {
      avg.nees.assign(m.steps(), 0.0);
      avg.nis.assign(m.steps(), 0.0);
    }
    for (std::size_t k = 0; k < m.steps(); ++k) {
      avg.nees[k] += m.nees[k] / kRuns;
      avg.nis[k] += m.chans[0].nis[k] / kRuns;
    }
  }
  for (const auto& [series, dof, name] :
       {std::tuple{&avg.nees, 4.0, "NEES"}, std::tuple{&avg.nis, 2.0, "NIS"}}) {
    const double lo = chi2_quantile(0.025, kRuns * dof) / kRuns;
    const double hi = chi2_quantile(0.975, kRuns * dof) / kRuns;
    std::size_t inside = 0;
    for (double e : *series)
      inside += e >= lo && e <= hi;
    const double fraction = static_cast<double>(inside) / static_cast<double>(series->size());
    const double mean = mean_finite(*series);
    EXPECT_GE(fraction, 0.90) << name;
    EXPECT_GE(mean, lo) << name;
    EXPECT_LE(mean, hi) << name;
    std::printf(
        "[ %s ] %s: time-averaged %.3f (bounds %.3f .. %.3f, dof %.0f), %.1f %% of steps "
        "inside\n",
        filter.c_str(), name, mean, lo, hi, dof, 100 * fraction);
  }
}

TEST(ModelRangeBearing, EkfIsConsistentOver50Runs) {
  check_consistency("ekf");
}

TEST(ModelRangeBearing, UkfIsConsistentOver50Runs) {
  check_consistency("ukf");
}

TEST(ModelRangeBearing, BearingCrossesPiAndItsInnovationIsWrapped) {
  auto s = load(preset_json());
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  const auto& bearing = d->col("bearing");
  bool near_plus = false, near_minus = false;
  for (double b : bearing) {
    EXPECT_GT(b, -std::numbers::pi);
    EXPECT_LE(b, std::numbers::pi);
    near_plus = near_plus || b > 3.0;
    near_minus = near_minus || b < -3.0;
  }
  EXPECT_TRUE(near_plus && near_minus) << "the pass crosses the ±π line";
  const auto& range = d->col("range");
  for (double r : range) {
    EXPECT_GT(r, 300.0);
    EXPECT_LT(r, 2000.0);
  }
  for (const char* filter : {"ekf", "ukf"}) {
    ASSERT_TRUE(s->params().apply_assignment(std::string("filter=") + filter, v).ok());
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& m = dynamic_cast<const model::ModelResult&>(**r);
    double worst = 0.0;
    for (double y : m.chans[0].y[1])
      worst = std::max(worst, std::fabs(y));
    EXPECT_LT(worst, 5 * v["sigma_bearing"]) << filter;
  }
  // The same model without the angle declaration sees a 2π jump in its innovation.
  auto j = preset_json();
  j["model"]["measurements"]["radar"]["roles"][1].erase("angle");
  auto plain = load(j);
  ASSERT_TRUE(plain);
  v["filter"] = 0;
  auto r = plain->run(*d, v);
  if (r.ok()) {
    double worst = 0.0;
    for (double y : dynamic_cast<const model::ModelResult&>(**r).chans[0].y[1])
      worst = std::isfinite(y) ? std::max(worst, std::fabs(y)) : worst;
    EXPECT_GT(worst, 3.0);
  }
}

}  // namespace
}  // namespace kfw
