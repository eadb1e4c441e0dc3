// Issue 30: a second closed loop from the library, presets/models/cart_lqr.json — a cart (double
// integrator) with its position measured and an LQR on the Kalman filter's estimate (certainty
// equivalence). A badly tuned R makes the loop worse: on a log grid of ratio 2 in R around the
// true σ_r², the tracking RMSE averaged over seeds 1..10 is lowest within one grid step of the
// true R. The controller's output is the filter's input (the push it predicts with), and the
// keys of a closed loop are refused with the key named.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/model_files.h"
#include "core/scenario.h"
#include "model/model_result.h"

namespace kfw {
namespace {

const std::string kCart = KFW_SOURCE_DIR "/presets/models/cart_lqr.json";

double mean_tracking_rmse(const Scenario& s, ParamValues v) {
  double sum = 0.0;
  for (int seed = 1; seed <= 10; ++seed) {
    v["sim.seed"] = seed;
    auto r = s.run(Dataset{}, v);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
    if (!r.ok()) return std::nan("");
    sum += (*r)->metrics.at("tracking_rmse");
  }
  return sum / 10.0;
}

TEST(ClosedLoopCart, TrackingIsBestNearTheTrueR) {
  auto s = testing::load_model_file(kCart);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  const double r_true = v["sim.sigma_r"] * v["sim.sigma_r"];
  std::vector<double> rmse;
  std::size_t best = 0;
  const int lo = -5, hi = 5;
  for (int j = lo; j <= hi; ++j) {
    v["R"] = r_true * std::pow(2.0, j);
    rmse.push_back(mean_tracking_rmse(*s, v));
    if (rmse.back() < rmse[best]) best = rmse.size() - 1;
  }
  const int at = static_cast<int>(best) + lo;
  EXPECT_LE(std::abs(at), 1) << "lowest at R = 2^" << at << " σ_r²";
  // Visibly worse at the grid's ends than at the true R.
  EXPECT_GT(rmse.front(), 1.05 * rmse[static_cast<std::size_t>(-lo)]);
  EXPECT_GT(rmse.back(), 1.05 * rmse[static_cast<std::size_t>(-lo)]);
}

TEST(ClosedLoopCart, ThePushIsTheFiltersInputAndIsSaturated) {
  auto s = testing::load_model_file(kCart);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["u_max"] = 0.5;
  auto r = s->run(Dataset{}, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const Dataset t = (*r)->table();
  const auto& u = t.col("u");
  double top = 0.0;
  for (double x : u)
    top = std::max(top, std::fabs(x));
  EXPECT_EQ(top, 0.5);  // the 1 m step asks for more at first
  // The filter predicts with the push it was given: with R tiny and q tiny the estimate follows
  // the true cart, which moves by that push.
  v["R"] = 1e-6;
  v["q"] = 1e-4;
  v["sim.q"] = 0.0;
  v["sim.sigma_r"] = 0.001;
  auto quiet = s->run(Dataset{}, v);
  ASSERT_TRUE(quiet.ok()) << quiet.error();
  EXPECT_LT((*quiet)->metrics.at("rmse.v"), 0.01);
}

TEST(ClosedLoopCart, ControllerKeysAreCheckedWithTheKeyNamed) {
  std::ifstream in(kCart);
  const auto base = nlohmann::json::parse(in);
  struct Case {
    const char* pointer;
    nlohmann::json value;
    const char* message;
  };
  const Case cases[] = {
      {"/model/controller/outputs/push", {{"expression", "1"}}, "model.controller.outputs.push"},
      {"/model/controller/outputs/u/expression", "k_p*pp", "unknown symbol 'pp'"},
      {"/model/controller/outputs/u/min", "p", "model.controller.outputs.u.min"},
      {"/model/controller/reference/expression", "p", "model.controller.reference.expression"},
      {"/model/controller/loop", {{"param", "nope"}}, "model.controller.loop.param"},
      {"/model/controller/noise_free", {{"free", "nope"}}, "model.controller.noise_free.free"},
      {"/model/controller/gains", 1, "model.controller.gains: unknown key"},
      {"/model/world/limits", {{"w", {{"min", "0"}}}}, "model.world.limits.w"},
      {"/model/world/events", {{"far", {{"when", "abs(pp)"}}}}, "model.world.events.far.when"},
      {"/model/measurements/fix/missing", {{"equals", "0"}}, "model.measurements.fix.missing"},
      {"/model/world/measurements/fix/impulses",
       {{"rate", "0.1"}},
       "model.world.measurements.fix.impulses"},
      {"/model/controller/outputs/u/expression", "heavisid(p)", "unknown function 'heavisid'"},
      {"/model/controller/outputs/u/unit", "N", "model.controller.outputs.u.unit: 'N', but"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.pointer);
    nlohmann::json j = base;
    j[nlohmann::json::json_pointer(c.pointer)] = c.value;
    auto s = make_model_scenario(j, "cart.json");
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.exit_code(), 2);
    EXPECT_NE(s.error().find(c.message), std::string::npos) << s.error();
    EXPECT_EQ(s.error().rfind("cart.json: ", 0), 0u) << s.error();
  }
}

}  // namespace
}  // namespace kfw
