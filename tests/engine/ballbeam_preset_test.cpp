// Seed 003 on its model file presets/ballbeam.json (issue 30 retired the built-in `ballbeam`):
// detection on stays close to the noise-free loop while detection off degrades (Figs. 8, 9), the
// simulated log is the closed loop's and is reproducible, replaying it reproduces the in-loop
// filter, bad input is a clear error, Table 1's α, β, the table of a run, the KF's settled gain,
// and the ball leaving the beam and the beam leaving the small-angle range (the world's events
// `left_beam` and `small_angle`, in the loop and in a replayed log's truth). One run is one loop:
// detection on and off are two runs; replay is the file's `mode` choice (closed 0, replay 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "core/statistics.h"
#include "document/preset.h"
#include "model/model_result.h"
#include "oracles/ballbeam/ballbeam_loop.h"

namespace kfw {
namespace {

constexpr double kBallbeamReplay = 1.0;  // `mode` choice index

struct BallbeamFile {
  std::shared_ptr<const Scenario> s;
  ParamValues v;  // the file's values
};

BallbeamFile ballbeam_file() {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/ballbeam.json");
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error());
  if (!p.ok()) return {};
  return {p->instance, p->values};
}

struct BallbeamRun {
  std::shared_ptr<const model::ModelResult> r;
  Dataset table;
};

BallbeamRun ballbeam_run(const Scenario& s, const Dataset& d, const ParamValues& v) {
  auto r = s.run(d, v);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return {};
  BallbeamRun out{std::dynamic_pointer_cast<const model::ModelResult>(*r), {}};
  EXPECT_TRUE(out.r);
  if (out.r) out.table = out.r->table();
  return out;
}

// RMS of column `of` minus the set point x_c from the step on (t ≥ sim.step_time), as the file's
// tracking_rmse (of truth.x) reads it.
double ballbeam_tracking_rms(const Dataset& table, const std::string& of, double step_time) {
  const auto& t = table.col("t");
  const auto& x = table.col(of);
  const auto& xc = table.col("derived.set_point");
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < step_time - 1e-9 || !std::isfinite(x[k] - xc[k])) continue;
    sum += (x[k] - xc[k]) * (x[k] - xc[k]);
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : std::nan("");
}

bool ballbeam_warned(const RunResult& r, const std::string& a, const std::string& b = "") {
  return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) {
    return w.find(a) != std::string::npos && w.find(b) != std::string::npos;
  });
}

TEST(BallbeamPreset, DetectionOnIsCloseToNoiseFreeAndOffIsDegraded) {
  const BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  const BallbeamRun on = ballbeam_run(*f.s, Dataset{}, f.v);
  ParamValues off_values = f.v;
  off_values["detection"] = 0;
  const BallbeamRun off = ballbeam_run(*f.s, Dataset{}, off_values);
  ASSERT_TRUE(on.r && off.r);
  const Metrics &m = on.r->metrics, &k = off.r->metrics;
  EXPECT_GT(m.at("impulsive_fraction.position"), 0.02);
  // Figs. 8, 9: with the circuit the step response stays close to the noise-free one; without
  // it the impulses reach the controller through the estimate.
  EXPECT_LT(m.at("tracking_excess") * 5, k.at("tracking_excess"));
  EXPECT_LT(m.at("rmse") * 5, k.at("rmse"));
  const double step = f.v.at("sim.step_time");
  ASSERT_NEAR(ballbeam_tracking_rms(on.table, "truth.x", step), m.at("tracking_rmse"), 1e-12);
  // The noise-free loop over the whole run, from the step (as the built-in's
  // tracking_rmse_noise_free); the off run's RMSE is up to its fall.
  const double noise_free = ballbeam_tracking_rms(on.table, "derived.noise_free", step);
  EXPECT_LT(m.at("tracking_rmse"), 1.2 * noise_free);
  EXPECT_GT(k.at("tracking_rmse"), 1.5 * noise_free);
  EXPECT_EQ(m.at("rmse"), m.at("rmse.x"));  // rmse: the primary state x
  // The circuit flags every contact loss; without it no sample is skipped.
  EXPECT_EQ(m.at("flagged_fraction.position"), m.at("impulsive_fraction.position"));
  EXPECT_EQ(k.at("flagged_fraction.position"), 0.0);
  // The noise-free reference is the same loop whichever detection runs (the off run is shorter:
  // on seed 3 the ball falls at 7.56 s without the circuit).
  const auto &nf_on = on.table.col("x_noise_free"), &nf_off = off.table.col("x_noise_free");
  ASSERT_LT(nf_off.size(), nf_on.size());
  EXPECT_TRUE(std::equal(nf_off.begin(), nf_off.end(), nf_on.begin()));
  // The steady filter (the file's choice) runs α, β: the closed form of eq. 16 equals the DARE.
  ASSERT_EQ(f.v.at("filter"), 1.0);
  for (const Dataset* table : {&on.table, &off.table}) {
    for (double K1 : table->col("K.x.x_meas")) {
      if (std::isfinite(K1)) {
        ASSERT_NEAR(K1, m.at("derived.alpha"), 1e-8);
      }
    }
    for (double K2 : table->col("K.v.x_meas")) {
      if (std::isfinite(K2)) {
        ASSERT_NEAR(K2 * f.v.at("Ts"), m.at("derived.beta"), 1e-8);
      }
    }
  }
}

TEST(BallbeamPreset, SimulatedTruthEqualsTheClosedLoopRun) {
  BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  for (double kind : {0.0, 1.0}) {
    f.v["filter"] = kind;
    auto d = f.s->simulate(f.v);
    ASSERT_TRUE(d.ok()) << d.error();
    const BallbeamRun r = ballbeam_run(*f.s, Dataset{}, f.v);
    ASSERT_TRUE(r.r);
    EXPECT_EQ(d->col("truth"), r.table.col("truth.x"));
    EXPECT_EQ(d->col("x_meas"), r.table.col("x_meas"));
    // Reproducible: the same seed gives the same log; another seed another.
    EXPECT_EQ(f.s->simulate(f.v)->col("x_meas"), d->col("x_meas"));
    ParamValues other = f.v;
    other["sim.seed"] = 4;
    EXPECT_NE(f.s->simulate(other)->col("x_meas"), d->col("x_meas"));
  }
}

TEST(BallbeamPreset, ReplayOfTheLogReproducesTheInLoopFilter) {
  BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  for (double kind : {0.0, 1.0}) {
    f.v["filter"] = kind;
    auto d = f.s->simulate(f.v);
    ASSERT_TRUE(d.ok()) << d.error();
    const BallbeamRun closed = ballbeam_run(*f.s, Dataset{}, f.v);
    ParamValues rv = f.v;
    rv["mode"] = kBallbeamReplay;
    const BallbeamRun replayed = ballbeam_run(*f.s, *d, rv);
    ASSERT_TRUE(closed.r && replayed.r);
    ASSERT_EQ(replayed.r->steps(), closed.r->steps());
    const auto &a = replayed.table.col("x.x"), &b = closed.table.col("x.x");
    for (std::size_t k = 0; k < b.size(); ++k)
      ASSERT_NEAR(a[k], b[k], 1e-12) << "step " << k;
    const Metrics &mr = replayed.r->metrics, &mc = closed.r->metrics;
    EXPECT_NEAR(mr.at("rmse"), mc.at("rmse"), 1e-9);
    EXPECT_NEAR(mr.at("tracking_rmse"), mc.at("tracking_rmse"), 1e-12);
    EXPECT_EQ(mr.at("flagged_fraction.position"), mc.at("flagged_fraction.position"));
    // A log holds no noise-free loop to compare with.
    EXPECT_TRUE(replayed.r->undefined.count("tracking_excess"));
  }
}

TEST(BallbeamPreset, BadInputGivesClearMessages) {
  const BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  auto expect_error = [&](const Dataset& d, const ParamValues& v, const std::string& word) {
    auto r = f.s->run(d, v);
    ASSERT_FALSE(r.ok()) << word;
    EXPECT_NE(r.error().find(word), std::string::npos) << r.error();
  };
  for (auto [key, value] : {std::pair<const char*, double>{"Ts", 0.0},
                            {"Ts", -0.01},
                            {"Q", -1.0},
                            {"R", -4e-6},
                            {"sim.contact_loss_rate", 1.5},
                            {"sim.contact_loss_rate", -0.1},
                            {"Q", std::nan("")}}) {
    ParamValues v = f.v;
    v[key] = value;
    expect_error(Dataset{}, v, key);
    auto sim = f.s->simulate(v);
    ASSERT_FALSE(sim.ok()) << key;
    EXPECT_NE(sim.error().find(key), std::string::npos) << sim.error();
    auto gain = f.s->gain(v);
    ASSERT_FALSE(gain.ok()) << key;
    EXPECT_NE(gain.error().find(key), std::string::npos) << gain.error();
  }
  // Replay needs the time, the sensor column, the beam angle (the filter's input u^c = a3 θ)
  // and two rows for a sample period.
  ParamValues rv = f.v;
  rv["mode"] = kBallbeamReplay;
  Dataset d;
  d.source = "log.csv";
  expect_error(d, rv, "column 't'");
  d.add("t", 3) = {0.0, 0.01, 0.02};
  d.add("theta", 3) = {0.0, 0.0, 0.0};
  expect_error(d, rv, "column 'x_meas'");
  Dataset one;
  one.source = "log.csv";
  one.add("t", 1) = {0.0};
  one.add("x_meas", 1) = {0.0};
  expect_error(one, rv, "column 'theta'");
  one.add("theta", 1) = {0.0};
  expect_error(one, rv, "two rows");
}

TEST(BallbeamPreset, StepAfterTheEndRunsWithoutAStep) {
  // sim.step_time is declared up to 100 s, sim.duration from 2 s: a step at or after the end of
  // the run leaves the set point at 0 — the tracking RMSE (from the step on) undefined with that
  // reason; never refused, never a NaN.
  BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  f.v["sim.step_time"] = 20;
  f.v["sim.duration"] = 5;
  auto r = f.s->run(Dataset{}, f.v);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ((*r)->steps(), 501u);
  ASSERT_TRUE((*r)->undefined.count("tracking_rmse"));
  EXPECT_EQ((*r)->undefined.at("tracking_rmse"), "the run ends before t = 20 s");
  EXPECT_FALSE((*r)->metrics.count("tracking_rmse"));
  for (const auto& [k, v] : (*r)->metrics)
    EXPECT_TRUE(std::isfinite(v)) << k;
}

TEST(BallbeamPreset, GainReportsClosedFormAndDare) {
  const BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  auto g = f.s->gain(f.v);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_NEAR(g->at("derived.lambda"), 0.0354, 5e-5);
  EXPECT_NEAR(g->at("derived.alpha"), 0.2335, 1e-4);  // seed 003 eq. 16; Table 1: 0.234, 0.031
  EXPECT_NEAR(g->at("derived.beta"), 0.0310, 1e-4);
  EXPECT_NEAR(g->at("K.x.x_meas"), g->at("derived.alpha"), 1e-8);  // the DARE's gain
  EXPECT_NEAR(g->at("K.v.x_meas") * g->at("dt"), g->at("derived.beta"), 1e-8);
}

TEST(BallbeamPreset, TableHoldsEstimatesAndTheThreeStepResponses) {
  // The run's table holds the estimate, the true ball, the set point and the noise-free loop
  // (the third response, detection off, is the run with detection = 0).
  const BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  auto d = f.s->simulate(f.v);
  ASSERT_TRUE(d.ok()) << d.error();
  for (const char* c : {"t", "x_meas", "v_sensor", "theta", "truth", "v_truth", "x_c", "V"})
    EXPECT_TRUE(d->has(c)) << c;
  const BallbeamRun r = ballbeam_run(*f.s, Dataset{}, f.v);
  ASSERT_TRUE(r.r);
  const Dataset& t = r.table;
  for (const char* c : {"t", "x_meas", "truth.x", "x.x", "x.v", "P.x", "S.x_meas", "nis.position",
                        "K.x.x_meas", "x_c", "V", "x_noise_free"})
    EXPECT_TRUE(t.has(c)) << c;
  EXPECT_EQ(t.rows(), r.r->steps());
  ASSERT_EQ(t.rows(), d->rows());
  // Fig. 7b: no update exactly where the circuit output is 0 V.
  for (std::size_t k = 0; k < t.rows(); ++k)
    ASSERT_EQ(d->col("v_sensor")[k] == 0.0, std::isnan(t.col("nis.position")[k])) << k;
}

TEST(BallbeamPreset, KfFinalGainIsTheSettledGainNotThePostGapOne) {
  BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  f.v["filter"] = 0;  // kf
  f.v["sim.seed"] = 6;
  const BallbeamRun r = ballbeam_run(*f.s, Dataset{}, f.v);
  ASSERT_TRUE(r.r);
  auto g = f.s->gain(f.v);
  ASSERT_TRUE(g.ok()) << g.error();
  const double alpha = r.r->metrics.at("derived.alpha"), beta = r.r->metrics.at("derived.beta");
  ballbeam::LoopTrace tr;
  tr.K1 = r.table.col("K.x.x_meas");
  tr.K2 = r.table.col("K.v.x_meas");
  // The last update of seed 6's run follows a contact loss: its gain is still well above α
  // (2.16 α).
  EXPECT_GT(last_finite(tr.K1), 1.2 * alpha);
  // Between contact losses the KF's gain settles on the steady-state (DARE, eq. 16) gain.
  const ballbeam::SettledGain settled = ballbeam::settled_gain(tr);
  EXPECT_NEAR(settled.K1, alpha, 1e-6);
  EXPECT_NEAR(settled.K1, g->at("K.x.x_meas"), 1e-6);
  EXPECT_NEAR(settled.K2 * f.v.at("Ts"), beta, 1e-6);
  EXPECT_GT(settled.run, 30u);
  // The steady filter uses the DARE gain (α) throughout.
  f.v["filter"] = 1;
  const BallbeamRun s = ballbeam_run(*f.s, Dataset{}, f.v);
  ASSERT_TRUE(s.r);
  tr.K1 = s.table.col("K.x.x_meas");
  tr.K2 = s.table.col("K.v.x_meas");
  const double K1 = ballbeam::settled_gain(tr).K1;
  EXPECT_NEAR(K1, g->at("K.x.x_meas"), 1e-12);
  EXPECT_NEAR(K1, alpha, 1e-8);
  for (double k : tr.K1)
    EXPECT_TRUE(std::isnan(k) || k == K1) << k;
}

TEST(BallbeamPreset, BallLeavingTheBeamIsWarnedWithTimeAndVariant) {
  BallbeamFile f = ballbeam_file();
  ASSERT_TRUE(f.s);
  // Seed 8: the ball stays on the beam with detection on and off (seed 3 drops it without the
  // circuit); no time to report, so the metric is undefined, with the reason. Without the
  // circuit the beam swings to its stops, far outside the small-angle model: a warning, and the
  // run goes on (the event does not end runs).
  for (double detection : {1.0, 0.0}) {
    SCOPED_TRACE(detection ? "detection on" : "detection off");
    ParamValues calm = f.v;
    calm["sim.seed"] = 8;
    calm["detection"] = detection;
    const BallbeamRun r = ballbeam_run(*f.s, Dataset{}, calm);
    ASSERT_TRUE(r.r);
    const Metrics& m = r.r->metrics;
    EXPECT_EQ(r.r->steps(), 1501u);
    EXPECT_EQ(m.at("event.left_beam"), 0.0);
    EXPECT_FALSE(m.count("event.left_beam_at_s"));
    ASSERT_TRUE(r.r->undefined.count("event.left_beam_at_s"));
    EXPECT_EQ(r.r->undefined.at("event.left_beam_at_s"), "the event did not occur in the run");
    EXPECT_FALSE(ballbeam_warned(*r.r, "off the beam"));
    const bool small = detection == 0.0;
    EXPECT_EQ(m.at("event.small_angle"), small ? 1.0 : 0.0);
    EXPECT_EQ(m.at("max_abs_theta") > 0.25, small);
    EXPECT_EQ(
        ballbeam_warned(*r.r, "beyond the small-angle range", "(model.world.events.small_angle)"),
        small);
    if (small) {
      std::ostringstream at;
      at << "at t = " << m.at("event.small_angle_at_s") << " s (";
      EXPECT_TRUE(ballbeam_warned(*r.r, "small-angle", at.str()));
    }
  }

  // Contact losses of 100 samples on average: the ball rolls off, with detection on too.
  f.v["sim.burst"] = 100;
  for (double detection : {0.0, 1.0}) {
    f.v["detection"] = detection;
    const BallbeamRun r = ballbeam_run(*f.s, Dataset{}, f.v);
    ASSERT_TRUE(r.r);
    const Metrics& m = r.r->metrics;
    ASSERT_EQ(m.at("event.left_beam"), 1.0);
    const double at = m.at("event.left_beam_at_s");
    EXPECT_GT(at, f.v.at("sim.step_time"));
    // The ball fell off there: the run stops at the last sample before, and says so.
    const auto& t = r.table.col("t");
    ASSERT_GT(t.size(), 1u);
    EXPECT_LT(t.size(), 1501u);
    EXPECT_NEAR(t.back() + f.v.at("Ts"), at, 1e-12);
    for (double x : r.table.col("truth.x"))
      EXPECT_LE(std::abs(x), 0.2);
    EXPECT_TRUE(std::isfinite(r.table.col("x.x").back()));
    // The noise-free loop keeps the ball (it runs on, cut to this run's rows).
    EXPECT_TRUE(std::isfinite(r.table.col("x_noise_free").back()));
    std::ostringstream os;
    os << "ball off the beam at t = " << at << " s: the run ends there";
    EXPECT_TRUE(ballbeam_warned(*r.r, os.str(), "(model.world.events.left_beam)"));
  }

  // The simulated log ends where the ball fell; a replayed log whose truth leaves the beam says
  // when, and the replay runs on to the log's end.
  auto d = f.s->simulate(f.v);
  ASSERT_TRUE(d.ok()) << d.error();
  const BallbeamRun fell = ballbeam_run(*f.s, Dataset{}, f.v);
  ASSERT_TRUE(fell.r);
  EXPECT_EQ(d->rows(), fell.r->steps());
  auto& truth = d->columns[static_cast<std::size_t>(
      std::find(d->names.begin(), d->names.end(), "truth") - d->names.begin())];
  truth[20] = 0.25;
  f.v["mode"] = kBallbeamReplay;
  const BallbeamRun replayed = ballbeam_run(*f.s, *d, f.v);
  ASSERT_TRUE(replayed.r);
  EXPECT_EQ(replayed.r->steps(), d->rows());
  EXPECT_EQ(replayed.r->metrics.at("event.left_beam"), 1.0);
  EXPECT_EQ(replayed.r->metrics.at("event.left_beam_at_s"), d->col("t")[20]);
  EXPECT_TRUE(ballbeam_warned(*replayed.r, "ball off the beam at t = ", "in the log's truth"));
}

}  // namespace
}  // namespace kfw
