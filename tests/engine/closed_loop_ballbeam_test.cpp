// Issue 30: seed 003's ball-and-beam as a model file (presets/ballbeam.json) with a closed loop.
// The world's sensor draws the retired built-in's streams (channel, dropout, burst and impulse of
// `position`), and the built-in's loop (now the oracle tests/oracles/ballbeam) and the file's run
// the same trajectory: the true ball, the estimate and the motor voltage agree to 1e-9 in
// ../shared/STAGE.md's form, and the ball leaves the beam in the same seeds at the same row,
// over seeds 1..10 with detection on and off: with detection off in several, with it on in none.
// α, β of the file's derived quantities equal the closed form and the DARE gain of the tracking
// filter to 1e-9.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/model_files.h"
#include "core/scenario.h"
#include "model/model_result.h"
#include "oracles/ballbeam/alpha_beta.h"
#include "oracles/ballbeam/ballbeam_loop.h"

namespace kfw {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/ballbeam.json";

struct Runs {
  ballbeam::LoopTrace builtin;
  std::shared_ptr<const model::ModelResult> model;
  Dataset table;
};

Runs run_both(const Scenario& s, int seed, bool detection) {
  ParamValues v = s.params().defaults();
  v["sim.seed"] = seed;
  v["detection"] = detection ? 1.0 : 0.0;
  v["filter"] = 0.0;  // kf: the built-in's steady filter takes α, β from the closed form
  Runs out;
  auto r = s.run(Dataset{}, v);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return out;
  out.model = std::dynamic_pointer_cast<const model::ModelResult>(*r);
  out.table = out.model->table();
  ballbeam::LoopParams p;
  p.seed = static_cast<std::uint64_t>(seed);
  ballbeam::TrackerParams tp;
  tp.Ts_s = p.Ts_s;
  tp.Q = v["Q"];
  tp.R = v["R"];
  tp.kind = ballbeam::FilterKind::kKalman;
  auto tracker = ballbeam::BallTracker::make(tp);
  EXPECT_TRUE(tracker.ok());
  ballbeam::LoopOptions opt;
  opt.detection = detection;
  const auto n = ballbeam::loop_steps(p);
  out.builtin = ballbeam::run_closed_loop(p, *tracker, ballbeam::make_disturbances(n, p), opt);
  return out;
}

// |a − b| ≤ tol (|b| + scale) at every row (STAGE.md).
void expect_close(const std::vector<double>& a, const std::vector<double>& b,
                  const std::vector<double>& scale, double tol, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  int bad = 0;
  for (std::size_t k = 0; k < b.size() && bad < 3; ++k) {
    const double bound = tol * (std::fabs(b[k]) + scale[k]);
    if (!(std::fabs(a[k] - b[k]) <= bound)) {
      ADD_FAILURE() << what << " at row " << k << ": " << a[k] << " vs " << b[k];
      ++bad;
    }
  }
}

std::vector<double> sqrt_of(const std::vector<double>& v) {
  std::vector<double> out;
  for (double x : v)
    out.push_back(std::sqrt(x));
  return out;
}

TEST(ClosedLoopBallbeam, TheModelsStreamsDriveTheBuiltInsLoopToTheSameTrajectory) {
  auto s = testing::load_model_file(kFile);
  ASSERT_TRUE(s);
  int fell_off = 0, fell_on = 0;
  for (int seed = 1; seed <= 10; ++seed) {
    for (bool detection : {true, false}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + (detection ? ", detection on" : ", off"));
      const Runs r = run_both(*s, seed, detection);
      ASSERT_TRUE(r.model);
      const auto& b = r.builtin;
      ASSERT_EQ(r.model->steps(), b.t.size());
      const std::vector<double> x_scale(b.t.size(), 0.2), v_scale(b.t.size(), 12.0);
      expect_close(r.table.col("truth.x"), b.x_true, x_scale, 1e-9, "true ball position");
      expect_close(r.table.col("x.x"), b.x_hat, sqrt_of(b.P11), 1e-9, "estimated position");
      expect_close(r.table.col("x.v"), b.v_hat, sqrt_of(b.P22), 1e-9, "estimated velocity");
      expect_close(r.table.col("V"), b.V, v_scale, 1e-9, "motor voltage");
      const auto& m = r.model->metrics;
      const bool fell = m.count("event.left_beam_at_s") > 0;
      EXPECT_EQ(fell, b.fell);
      if (fell) {
        EXPECT_DOUBLE_EQ(m.at("event.left_beam_at_s"), b.left_beam_at_s);
        ++(detection ? fell_on : fell_off);
      }
    }
  }
  EXPECT_GE(fell_off, 3);
  EXPECT_EQ(fell_on, 0);
}

TEST(ClosedLoopBallbeam, AnEventEndsTheRunWithExitZeroAndItsResultsUpToThen) {
  auto s = testing::load_model_file(kFile);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["detection"] = 0.0;
  for (int seed = 1; seed <= 10; ++seed) {
    v["sim.seed"] = seed;
    auto r = s->run(Dataset{}, v);
    ASSERT_TRUE(r.ok()) << r.error();
    if (!(*r)->metrics.count("event.left_beam_at_s")) continue;
    const double at = (*r)->metrics.at("event.left_beam_at_s");
    EXPECT_LT((*r)->t.back(), at);
    EXPECT_LT(at, v["sim.duration"]);
    const auto& w = (*r)->warnings;
    EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& line) {
      return line.find("ball off the beam at t = ") == 0;
    }));
    return;
  }
  FAIL() << "no seed of 1..10 dropped the ball with detection off";
}

TEST(ClosedLoopBallbeam, AlphaBetaEqualTheClosedFormAndTheDareGain) {
  auto s = testing::load_model_file(kFile);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  for (double Q : {0.05, 0.5013, 50.0}) {
    v["Q"] = Q;
    auto r = s->run(Dataset{}, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& m = (*r)->metrics;
    const ballbeam::AlphaBeta ab = ballbeam::alpha_beta(ballbeam::tracking_index(0.01, Q, v["R"]));
    EXPECT_NEAR(m.at("derived.alpha"), ab.alpha, 1e-9 * ab.alpha);
    EXPECT_NEAR(m.at("derived.beta"), ab.beta, 1e-9 * ab.beta);
    auto g = s->gain(v);
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_NEAR(g->at("K.x.x_meas"), ab.alpha, 1e-9 * ab.alpha);
    EXPECT_NEAR(g->at("K.v.x_meas") * 0.01, ab.beta, 1e-9 * ab.beta);
  }
}

}  // namespace
}  // namespace kfw
