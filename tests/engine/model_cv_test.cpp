// Constant-velocity model files: the DARE gain of presets/models/cv1d.json is the closed-form
// α-β filter of seed 003; on a linear model KF, EKF and UKF agree, and the KF is the textbook
// filter of filter/kalman_filter.h.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/model_files.h"
#include "core/scenario.h"
#include "filter/kalman_filter.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "oracles/ballbeam/alpha_beta.h"

namespace kfw {
namespace {

using testing::kModelDir;
using testing::load_model;

const model::ModelResult& as_model(const std::shared_ptr<const RunResult>& r) {
  return dynamic_cast<const model::ModelResult&>(*r);
}

TEST(ModelCv, DareGainIsTheAlphaBetaFilter) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  const double T = v["sim.dt"], sigma_r = v["sigma_r"];
  for (double lambda : {0.0354, 0.1, 1.0, 5.0}) {
    // λ = σ_a T² / σ_r (seed 003, eq. 16 with Q = σ_a², R = σ_r²).
    v["sigma_a"] = lambda * sigma_r / (T * T);
    auto g = s->gain(v);
    ASSERT_TRUE(g.ok()) << g.error();
    const auto ab = ballbeam::alpha_beta(lambda);
    EXPECT_NEAR(g->at("K.x.z"), ab.alpha, 1e-9) << "λ = " << lambda;
    EXPECT_NEAR(g->at("K.v.z") * T, ab.beta, 1e-9) << "λ = " << lambda;
    EXPECT_EQ(g->at("dt"), T);
  }
}

TEST(ModelCv, GainUsesTheDatasetsSamplePeriod) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["sim.dt"] = 0.05;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  v["sim.dt"] = 0.1;
  auto g = s->gain(v, &*d);
  ASSERT_TRUE(g.ok());
  EXPECT_NEAR(g->at("dt"), 0.05, 1e-12);
  const auto ab = ballbeam::alpha_beta(v["sigma_a"] * 0.05 * 0.05 / v["sigma_r"]);
  EXPECT_NEAR(g->at("K.x.z"), ab.alpha, 1e-9);
}

TEST(ModelCv, KfIsTheTextbookFilterAndReachesTheDareGain) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& m = as_model(*r);
  // The same recursion through kalman_filter.h.
  const double T = v["sim.dt"], sa2 = v["sigma_a"] * v["sigma_a"];
  Mat<2> F;
  F << 1, T, 0, 1;
  Covariance<2> Q;
  Q << T * T * T * T / 4 * sa2, T * T * T / 2 * sa2, T * T * T / 2 * sa2, T * T * sa2;
  const Mat<1, 2> H(1.0, 0.0);
  const double R = v["sigma_r"] * v["sigma_r"];
  const auto& z = d->col("z");
  Gaussian<2> g;
  g.x << z[0], 0.0;
  g.P << v["P0_x"], 0, 0, v["P0_v"];
  for (std::size_t k = 0; k < d->rows(); ++k) {
    if (k > 0) g = predict(g, F, Vec<2>(Vec<2>::Zero()), Q);
    g = update_scalar(g, z[k], H, R).post;
    ASSERT_NEAR(m.x[0][k], g.x(0), 1e-9 * (1 + std::fabs(g.x(0)))) << k;
    ASSERT_NEAR(m.x[1][k], g.x(1), 1e-9 * (1 + std::fabs(g.x(1)))) << k;
    ASSERT_NEAR(m.P[m.cov_index(0, 1)][k], g.P(0, 1), 1e-12 * (1 + std::fabs(g.P(0, 1)))) << k;
  }
  auto gain = s->gain(v);
  ASSERT_TRUE(gain.ok());
  EXPECT_NEAR(m.chans[0].K[0].back(), gain->at("K.x.z"), 1e-9);
  EXPECT_NEAR(m.chans[0].K[1].back(), gain->at("K.v.z"), 1e-9);
}

// Uneven sampling: a clock that repeats a few intervals (the process matrices come from the
// per-dt cache) and one that never repeats; both equal the textbook filter with that step's F, Q.
TEST(ModelCv, UnevenSamplingUsesEachRowsDt) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  auto sim = s->simulate(v);
  ASSERT_TRUE(sim.ok());
  const double sa2 = v["sigma_a"] * v["sigma_a"], R = v["sigma_r"] * v["sigma_r"];
  for (int clock = 0; clock < 2; ++clock) {
    Dataset d = *sim;
    auto& t = d.columns[static_cast<std::size_t>(d.index("t"))];
    const double steps[] = {0.1, 0.25, 0.1, 0.05, 0.3};
    for (std::size_t k = 1; k < t.size(); ++k)
      t[k] = t[k - 1] + (clock == 0 ? steps[k % 5] : 0.1 + 1e-4 * std::sin(0.7 * k));
    auto r = s->run(d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& m = as_model(*r);
    const auto& z = d.col("z");
    Gaussian<2> g;
    g.x << z[0], 0.0;
    g.P << v["P0_x"], 0, 0, v["P0_v"];
    for (std::size_t k = 0; k < d.rows(); ++k) {
      if (k > 0) {
        const double T = t[k] - t[k - 1];
        Mat<2> F;
        F << 1, T, 0, 1;
        Covariance<2> Q;
        Q << T * T * T * T / 4 * sa2, T * T * T / 2 * sa2, T * T * T / 2 * sa2, T * T * sa2;
        g = predict(g, F, Vec<2>(Vec<2>::Zero()), Q);
      }
      g = update_scalar(g, z[k], Mat<1, 2>(1.0, 0.0), R).post;
      ASSERT_NEAR(m.x[0][k], g.x(0), 1e-9 * (1 + std::fabs(g.x(0)))) << clock << " " << k;
      ASSERT_NEAR(m.x[1][k], g.x(1), 1e-9 * (1 + std::fabs(g.x(1)))) << clock << " " << k;
      ASSERT_NEAR(m.P[m.cov_index(1, 1)][k], g.P(1, 1), 1e-9 * (1 + g.P(1, 1))) << k;
    }
  }
}

// Two channels at their own rates (a speed sensor every 5th row) and a χ² gate on the position.
TEST(ModelCv, ChannelsAtTheirOwnRatesAndAGate) {
  std::ifstream in(kModelDir + "cv1d.json");
  auto j = nlohmann::json::parse(in);
  j["model"]["measurements"]["speed"] = nlohmann::json::parse(
      R"({"roles": [{"name": "vz", "unit": "m/s"}], "H": [["0", "1"]], "R": ["0.01"],
          "every": 5})");
  j["model"]["measurements"]["position"]["gate"] = 0.99999;
  auto s = make_model_scenario(j, "cv1d+speed");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  const auto& vz = d->col("vz");
  for (std::size_t k = 0; k < vz.size(); ++k)
    ASSERT_EQ(std::isfinite(vz[k]), k % 5 == 0) << k;
  auto& z = d->columns[static_cast<std::size_t>(d->index("z"))];
  for (std::size_t k : {100u, 200u, 250u, 400u, 555u})
    z[k] += 1000.0;
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& m = as_model(*r);
  ASSERT_EQ(m.chans.size(), 2u);
  EXPECT_EQ(m.chans[0].name, "position");
  EXPECT_EQ(m.chans[1].name, "speed");
  EXPECT_EQ(m.chans[1].updates, (d->rows() + 4) / 5);
  EXPECT_EQ(m.chans[0].gated, 5u);
  EXPECT_EQ(m.chans[0].updates, d->rows() - 5);
  EXPECT_EQ((*r)->metrics.at("gated.position"), 5.0);
  EXPECT_LT((*r)->metrics.at("rmse"), 2.0);
  EXPECT_TRUE((*r)->metrics.count("nis_mean.speed"));
  EXPECT_TRUE(std::isnan(m.chans[0].nis[100]));
  EXPECT_GT(m.chans[0].y[0][100], 900.0);
}

// KF and EKF to 1e-12, UKF (α = 1, β = 0, κ = 0: exact for a linear model) to 1e-9, on the
// scalar channel of cv1d and the 2-D channel of cv2d.
void expect_filters_agree(const Scenario* s) {
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  v["ukf.alpha"] = 1.0;
  v["ukf.beta"] = 0.0;
  v["ukf.kappa"] = 0.0;
  std::vector<std::shared_ptr<const RunResult>> runs;
  for (const char* f : {"kf", "ekf", "ukf"}) {
    ASSERT_TRUE(s->params().apply_assignment(std::string("filter=") + f, v).ok());
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(as_model(*r).filter, f);
    runs.push_back(*r);
  }
  const auto& kf = as_model(runs[0]);
  for (std::size_t which : {1u, 2u}) {
    const auto& other = as_model(runs[which]);
    const double tol = which == 1 ? 1e-12 : 1e-9;
    for (std::size_t i = 0; i < kf.x.size(); ++i) {
      for (std::size_t k = 0; k < kf.t.size(); ++k) {
        const double a = kf.x[i][k], b = other.x[i][k];
        ASSERT_LE(std::fabs(a - b), tol * std::max(1.0, std::fabs(a))) << other.filter << k;
      }
    }
    for (std::size_t e = 0; e < kf.P.size(); ++e) {
      for (std::size_t k = 0; k < kf.t.size(); ++k) {
        const double a = kf.P[e][k], b = other.P[e][k];
        ASSERT_LE(std::fabs(a - b), tol * std::max(1e-3, std::fabs(a))) << other.filter << k;
      }
    }
    for (std::size_t k = 0; k < kf.t.size(); ++k) {
      const double a = kf.chans[0].nis[k], b = other.chans[0].nis[k];
      if (std::isnan(a)) continue;
      ASSERT_LE(std::fabs(a - b), tol * std::max(1.0, a) * 10) << other.filter << k;
    }
  }
}

TEST(ModelCv, KfEkfUkfAgreeOnALinearModel) {
  for (const char* file : {"cv1d.json", "cv2d.json", "ca1d.json"}) {
    SCOPED_TRACE(file);
    expect_filters_agree(load_model(file).get());
  }
}

// A zero initial velocity variance: P has no Cholesky factor at the first update and prediction,
// so the UKF draws its sigma points from the symmetric square root — and still equals the KF.
TEST(ModelCv, UkfOfASingularCovarianceEqualsTheKf) {
  std::ifstream in(kModelDir + "cv1d.json");
  auto j = nlohmann::json::parse(in);
  j["model"]["P0"] = {"P0_x", "0"};
  auto s = make_model_scenario(j, "cv1d with P0_v = 0");
  ASSERT_TRUE(s.ok()) << s.error();
  expect_filters_agree(s->get());
  ParamValues v = (*s)->params().defaults();
  ASSERT_TRUE((*s)->params().apply_assignment("filter=ukf", v).ok());
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& m = as_model(*r);
  EXPECT_EQ(m.P[m.diag[1]][0], 0.0);  // the velocity variance after the first update
  EXPECT_GT(m.P[m.diag[1]][1], 0.0);  // the prediction's Q drives it
}

TEST(ModelCv, ContinuousFormIsVanLoan) {
  // ca1d (white jerk, continuous form): the discrete Q of Van Loan is the textbook one,
  // Q = q [[T⁵/20, T⁴/8, T³/6], [T⁴/8, T³/3, T²/2], [T³/6, T²/2, T]] (Bar-Shalom 2001, 6.2.3);
  // its steady state therefore equals that of the same model written with F and Q.
  auto s = load_model("ca1d.json");
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  auto g = s->gain(v);
  ASSERT_TRUE(g.ok()) << g.error();
  std::ifstream in(kModelDir + "ca1d.json");
  auto j = nlohmann::json::parse(in);
  j["model"]["process"] = {{"F", {{"1", "dt", "dt^2/2"}, {"0", "1", "dt"}, {"0", "0", "1"}}},
                           {"Q",
                            {{"q_jerk*dt^5/20", "q_jerk*dt^4/8", "q_jerk*dt^3/6"},
                             {"q_jerk*dt^4/8", "q_jerk*dt^3/3", "q_jerk*dt^2/2"},
                             {"q_jerk*dt^3/6", "q_jerk*dt^2/2", "q_jerk*dt"}}}};
  auto discrete = make_model_scenario(j, "ca1d discrete");
  ASSERT_TRUE(discrete.ok()) << discrete.error();
  auto gd = (*discrete)->gain(v);
  ASSERT_TRUE(gd.ok());
  for (const char* key : {"K.x.z", "K.v.z", "K.a.z", "P_pred.x", "P_pred.v.a"})
    EXPECT_NEAR(g->at(key), gd->at(key), 1e-9 * std::max(1.0, std::fabs(gd->at(key)))) << key;
}

}  // namespace
}  // namespace kfw
