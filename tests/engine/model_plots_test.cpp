// Issue 27, plot blocks of a model file ("plots", engine/model/plots/model_plots.h): each kind's
// keys are checked when the file loads (key paths, "did you mean", version 2 only), and the numbers
// a block shows come from the engine — the gain_curve block's k1 against β is the closed form k1(β)
// and `kfw-cli gain --curve Q --x beta` (1e-9), a series block's data is the run's column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/scenario.h"
#include "experiment/gain_curve.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "model/plots/model_plots.h"

namespace kfw {
namespace model_plots_test {
namespace {

using nlohmann::json;

json load(const char* name) {
  std::ifstream in(std::string(KFW_SOURCE_DIR "/presets/models/") + name);
  return json::parse(in);
}

// The README's examples of plot blocks, each a "plots" list (section "Plot blocks").
std::vector<json> readme_examples() {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/README.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string readme = ss.str();
  std::vector<json> out;
  auto at = readme.find("**Plot blocks**");
  const auto end = readme.find("\n**", at + 4);
  while (at != std::string::npos) {
    const auto open = readme.find("```json\n", at);
    if (open == std::string::npos || open > end) break;
    const auto close = readme.find("```", open + 8);
    out.push_back(json::parse("{" + readme.substr(open + 8, close - open - 8) + "}"));
    at = close + 3;
  }
  return out;
}

// The helicopter model file with the README's blocks and a derived series of its own.
json helicopter_with_plots() {
  json p = load("../helicopter.json");
  p["model"]["derived"]["err_theta"] = {
      {"expression", "theta - truth"}, {"unit", "deg"}, {"label", "angle error"}};
  p["model"]["plots"] = json::array();
  const auto examples = readme_examples();
  for (std::size_t i = 0; i < 2 && i < examples.size(); ++i) {
    for (const json& b : examples[i].at("plots"))
      p["model"]["plots"].push_back(b);
  }
  return p;
}

// cv2d.json with the README's trajectory block (and its covariance block, `covariance`).
json cv2d_with_top_view(bool covariance = false) {
  json p = load("cv2d.json");
  p["model"]["version"] = 2;
  const auto examples = readme_examples();
  if (examples.size() < 4) return p;
  p["model"]["plots"] = examples[2].at("plots");
  if (covariance) {
    p["model"]["derived"] = examples[3].at("derived");
    p["model"]["plots"].push_back(examples[3].at("plots")[0]);
  }
  return p;
}

std::string refusal(const json& p) {
  auto s = make_model_scenario(p, "heli.json");
  return s.ok() ? std::string("(loaded)") : s.error();
}

double k1_closed_form(double b) {
  const double p = std::sqrt(b) * (std::sqrt(1 + 0.25 * b) + 0.5 * std::sqrt(b));
  return p / (1 + p);
}

TEST(ModelPlots, TheReadmeExamplesLoadAsDeclared) {
  const auto examples = readme_examples();
  ASSERT_EQ(examples.size(), 4u) << "one example per kind";
  auto s = make_model_scenario(helicopter_with_plots(), "heli.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const auto layout = model_layout_of(**s);
  ASSERT_TRUE(layout);
  ASSERT_EQ(layout->plots.size(), 2u);
  const model::PlotBlockSpec& g = layout->plots[0];
  EXPECT_EQ(g.kind, "gain_curve");
  EXPECT_EQ(g.id, "beta_curve");
  EXPECT_EQ(g.sweep, "Q");
  EXPECT_EQ(g.x.key, "derived.beta");
  ASSERT_EQ(g.y.size(), 2u);
  EXPECT_EQ(g.y[0].key, "derived.k1");
  EXPECT_EQ(g.y[1].key, "K.theta.angle");
  ASSERT_EQ(g.y2.size(), 1u);
  EXPECT_EQ(g.y2[0].label, "p11⁻/N_θ, closed form");
  EXPECT_TRUE(g.log_x && g.log_y && g.log_y2 && g.operating_point);
  const model::PlotBlockSpec& t = layout->plots[1];
  EXPECT_EQ(t.kind, "series");
  ASSERT_EQ(t.series.size(), 2u);
  EXPECT_EQ(t.series[0].key, "derived.err_theta");
  EXPECT_EQ(t.series[0].unit, "deg");
  EXPECT_EQ(t.series[1].key, "theta");
  EXPECT_EQ(t.series[1].label, "θ (angle)");
}

// k1 and p11⁻/N_θ against β over the swept Q: the closed form (seed 000, eqs. 11-12), and the
// DARE gain K.theta.angle equal to what `kfw-cli gain --curve Q --x beta` prints (the same
// points when the block sweeps Q's whole range), for m = 1 and 5.
TEST(ModelPlots, TheGainCurveBlockIsTheClosedFormAndTheCliCurve) {
  json p = helicopter_with_plots();
  p["model"]["plots"][0].erase("range");
  auto s = make_model_scenario(p, "heli.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const model::PlotBlockSpec b = model_layout_of(**s)->plots[0];
  for (double m : {1.0, 5.0}) {
    ParamValues v = (*s)->params().defaults();
    v["m"] = m;
    auto c = gain_curve_of(**s, v, b.sweep, {"derived.k1", "K.theta.angle", "derived.p11_over_R"},
                           b.x.key, 100, nullptr, b.range_lo, b.range_hi);
    ASSERT_TRUE(c.ok()) << c.error();
    auto cli = gain_curve(**s, v, "Q", 100, nullptr, "K.", "beta");
    ASSERT_TRUE(cli.ok()) << cli.error();
    ASSERT_EQ(c->x_metric.size(), 100u);
    const auto k1_cli = static_cast<std::size_t>(
        std::find(cli->entries.begin(), cli->entries.end(), "K.theta.angle") -
        cli->entries.begin());
    ASSERT_LT(k1_cli, cli->entries.size());
    int checked = 0;
    for (std::size_t i = 0; i < c->x.size(); ++i) {
      const double beta = c->x_metric[i];
      EXPECT_NEAR(beta, m * 0.02 * 0.02 * c->x[i] / v.at("R"), 1e-12 * beta);
      EXPECT_NEAR(c->values[0][i], k1_closed_form(beta), 1e-9) << "beta " << beta;
      EXPECT_NEAR(c->values[1][i], k1_closed_form(beta), 1e-9) << "beta " << beta;
      EXPECT_NEAR(c->values[1][i], cli->values[k1_cli][i], 1e-12) << "beta " << beta;
      const double p11 = k1_closed_form(beta) / (1 - k1_closed_form(beta));
      EXPECT_NEAR(c->values[2][i], p11, 1e-9 * std::max(1.0, p11));
      checked += std::isfinite(c->values[1][i]);
    }
    EXPECT_EQ(checked, 100);
    // The operating point lies on the curve: the values at the current Q.
    EXPECT_NEAR(c->at[0], k1_closed_form(c->steady.at("derived.beta")), 1e-9);
  }
  // A declared range: the points span it.
  auto c = gain_curve_of(**s, (*s)->params().defaults(), "Q", {"derived.k1"}, "derived.beta", 10,
                         nullptr, 0.5, 5e5);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_DOUBLE_EQ(c->x.front(), 0.5);
  EXPECT_NEAR(c->x.back(), 5e5, 1e-6);
}

TEST(ModelPlots, TheSeriesBlockIsTheRunsColumn) {
  auto s = make_model_scenario(helicopter_with_plots(), "heli.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  v["sim.duration"] = 20;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& mr = dynamic_cast<const model::ModelResult&>(**r);
  const auto data = model::series_block_data(model_layout_of(**s)->plots[1], mr);
  ASSERT_EQ(data.size(), 2u);
  const Dataset table = mr.table();
  ASSERT_NE(data[0].y, nullptr);
  ASSERT_NE(data[1].y, nullptr);
  const auto& err = table.col("derived.err_theta");
  const auto& theta = table.col("x.theta");
  ASSERT_EQ(data[0].y->size(), err.size());
  int finite = 0;
  for (std::size_t k = 0; k < err.size(); ++k) {
    EXPECT_TRUE((*data[0].y)[k] == err[k] || (std::isnan(err[k]) && std::isnan((*data[0].y)[k])));
    EXPECT_EQ((*data[1].y)[k], theta[k]);
    finite += std::isfinite(err[k]);
  }
  EXPECT_GT(finite, 900);
}

TEST(ModelPlots, TheTrajectoryBlockIsTheRunsTracksAndItsPoints) {
  auto s = make_model_scenario(cv2d_with_top_view(), "cv2d.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const auto layout = model_layout_of(**s);
  ASSERT_EQ(layout->plots.size(), 1u);
  const model::PlotBlockSpec& b = layout->plots[0];
  EXPECT_EQ(b.kind, "trajectory");
  EXPECT_EQ(b.tx.key, "px");
  EXPECT_EQ(b.ty.unit, "m");
  ASSERT_EQ(b.points.size(), 2u);
  ParamValues v = (*s)->params().defaults();
  v["vx0"] = 3.0;
  v["vy0"] = -2.0;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& mr = dynamic_cast<const model::ModelResult&>(**r);
  const model::TrajectoryData t = model::trajectory_block_data(b, mr);
  const Dataset table = mr.table();
  ASSERT_TRUE(t.x && t.y && t.x_true && t.y_true);
  EXPECT_EQ(*t.x, table.col("x.px"));
  EXPECT_EQ(*t.y, table.col("x.py"));
  EXPECT_EQ(*t.x_true, d->col("px_true"));
  EXPECT_EQ(*t.y_true, d->col("py_true"));
  ASSERT_EQ(t.points.size(), 2u);
  // In the file's order of keys as the JSON reader keeps them (here sorted: "60 s ahead" first).
  for (const auto& p : t.points) {
    if (p.name == "start") {
      EXPECT_EQ(p.x, 0.0);
      EXPECT_EQ(p.y, 0.0);
    } else {
      EXPECT_EQ(p.name, "60 s ahead");
      EXPECT_DOUBLE_EQ(p.x, 180.0);
      EXPECT_DOUBLE_EQ(p.y, -120.0);
    }
  }
  json p = cv2d_with_top_view();
  p["model"]["plots"][0]["points"]["B1"] = {"px + 1", "0"};
  EXPECT_EQ(refusal(p).rfind("heli.json: model.plots[0].points.B1[0]: state 'px' cannot be used "
                             "here",
                             0),
            0u)
      << refusal(p);
  p = cv2d_with_top_view();
  p["model"]["plots"][0]["y"] = "pz";
  EXPECT_EQ(refusal(p), "heli.json: model.plots[0].y: unknown state 'pz' (did you mean 'px'?)");
}

// The sample covariance of the declared series (the run's derived columns) beside the design
// matrix at the run's values.
TEST(ModelPlots, TheCovarianceBlockIsTheSampleCovarianceBesideTheDesign) {
  auto s = make_model_scenario(cv2d_with_top_view(true), "cv2d.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const model::PlotBlockSpec b = model_layout_of(**s)->plots.at(1);
  EXPECT_EQ(b.kind, "covariance");
  ParamValues v = (*s)->params().defaults();
  v["sigma_r"] = 3.0;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& mr = dynamic_cast<const model::ModelResult&>(**r);
  const model::CovarianceData c = model::covariance_block_data(b, mr);
  ASSERT_EQ(c.n, 2u);
  EXPECT_EQ(c.design, (std::vector<double>{9.0, 0.0, 0.0, 9.0}));
  const Dataset table = mr.table();
  const auto& ex = table.col("derived.err_x");
  const auto& ey = table.col("derived.err_y");
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < ex.size(); ++k) {
    mx += ex[k];
    my += ey[k];
  }
  const double n = static_cast<double>(ex.size());
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t k = 0; k < ex.size(); ++k) {
    sxx += (ex[k] - mx) * (ex[k] - mx);
    sxy += (ex[k] - mx) * (ey[k] - my);
    syy += (ey[k] - my) * (ey[k] - my);
  }
  EXPECT_EQ(c.count, ex.size());
  EXPECT_NEAR(c.sample[0], sxx / (n - 1), 1e-12 * sxx / n);
  EXPECT_NEAR(c.sample[1], sxy / (n - 1), 1e-12 * sxx / n);
  EXPECT_EQ(c.sample[1], c.sample[2]);
  EXPECT_NEAR(c.sample[3], syy / (n - 1), 1e-12 * syy / n);
  json p = cv2d_with_top_view(true);
  p["model"]["plots"][1]["design"] =
      json::array({json::array({"1", "2"}), json::array({"3", "1"})});
  EXPECT_NE(refusal(p).find("model.plots[1].design: not symmetric"), std::string::npos)
      << refusal(p);
  p["model"]["plots"][1]["design"] = json::array({"1", "1", "1"});
  EXPECT_NE(refusal(p).find("model.plots[1].design: wrong dimensions"), std::string::npos)
      << refusal(p);
}

TEST(ModelPlots, MistakesAreNamedWithTheirKeyPath) {
  struct Case {
    const char* key;
    json value;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"kind", "gain_curv",
       "heli.json: model.plots[0].kind: unknown kind of plot 'gain_curv' (did you mean "
       "'gain_curve'?)"},
      {"sweeep", "Q",
       "heli.json: model.plots[0].sweeep: unknown key of a gain_curve block (did you mean "
       "'sweep'?)"},
      {"x", "betta",
       "heli.json: model.plots[0].x: unknown derived scalar 'betta' (did you mean 'beta'?)"},
      {"sweep", "QQ",
       "heli.json: model.plots[0].sweep: unknown continuous filter parameter 'QQ' (did you mean "
       "'Q'?)"},
      {"y", json::array({"derived.k1", "K.theta.angel"}),
       "heli.json: model.plots[0].y[1]: unknown quantity of the steady state 'K.theta.angel' (did "
       "you mean 'K.theta.angle'?)"},
      {"log", json::array({"x", "z"}),
       "heli.json: model.plots[0].log[1]: unknown axis 'z' (one of x, y, y2)"},
      {"range", json::array({1e3, 1}),
       "heli.json: model.plots[0].range: expected lowest < highest within Q's range [1e-06, "
       "1e+06]"},
      {"id", "gain", "heli.json: model.plots[0].id: 'gain' is a panel of the model view already"},
  };
  for (const auto& c : cases) {
    json p = helicopter_with_plots();
    p["model"]["plots"][0][c.key] = c.value;
    EXPECT_EQ(refusal(p), c.message) << c.key;
  }
  json p = helicopter_with_plots();
  p["model"]["plots"][1]["y"] = json::array({"theta", "derived.beta"});
  EXPECT_NE(refusal(p).find("model.plots[1].y[1]: derived.beta is a scalar"), std::string::npos)
      << refusal(p);
  p["model"]["plots"][1]["y"] = "thetta";
  EXPECT_EQ(refusal(p),
            "heli.json: model.plots[1].y: unknown state or derived series 'thetta' (did you mean "
            "'theta'?)");
  p = helicopter_with_plots();
  p["model"]["plots"][1]["id"] = "beta_curve";
  EXPECT_EQ(refusal(p), "heli.json: model.plots[1].id: 'beta_curve' is the id of another block");
  p = helicopter_with_plots();
  p["model"]["plots"][0].erase("y");
  EXPECT_EQ(refusal(p), "heli.json: model.plots[0]: missing key 'y'");
}

TEST(ModelPlots, AVersionOneFileIsRefusedAndAGainCurveNeedsASteadyState) {
  json p = load("cv1d.json");
  p["model"]["plots"] = json::array({{{"kind", "series"}, {"id", "pos"}, {"y", "x"}}});
  EXPECT_EQ(refusal(p), "heli.json: model.plots: a version-2 key: set \"version\": 2");
  p["model"]["version"] = 2;
  EXPECT_EQ(refusal(p), "(loaded)");
  json q = load("pendulum.json");
  q["model"]["version"] = 2;
  q["model"]["plots"] =
      json::array({{{"kind", "gain_curve"}, {"id", "k"}, {"sweep", "q"}, {"y", "K.theta.x"}}});
  EXPECT_NE(refusal(q).find("model.plots[0].kind: a gain curve needs a steady state"),
            std::string::npos)
      << refusal(q);
}

}  // namespace
}  // namespace model_plots_test
}  // namespace kfw
