// Issue 28: a model's modes filtered block by block (model.modes.structure): equal to Table 2 with
// each mode's mixed covariance block-diagonal (tests/oracles/imm_table2.h, 1e-9), `approximate`
// dropping R's cross-block entries, a choice parameter selecting the structure, and the
// refusals of blocks that F, H, Q, R or P0 couple; "detect" finding the blocks a model keeps apart
// exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "oracles/imm_table2.h"

namespace kfw {
namespace {

using nlohmann::json;

json st_list(std::initializer_list<nlohmann::detail::json_ref<json>> e) {
  return json::array(e);
}

// x, vx, y, vy: two decoupled constant-velocity axes, position (x, y) measured with a cross
// covariance c between its components; two modes of white acceleration.
json two_axis_preset(const json& structure, const char* c = "0") {
  const auto L = st_list;
  auto P = [](double v, double lo, double hi) {
    return json{{"value", v}, {"min", lo}, {"max", hi}, {"scale", "linear"}};
  };
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}};
  p["parameters"] = {
      {"q", P(0.2, 1e-3, 10)},
      {"q_man", P(2.0, 1e-3, 10)},
      {"r", P(1.0, 1e-3, 10)},
      {"c", P(0.4, -1, 1)},
      {"sim.dt", P(0.5, 0.01, 1)},
      {"sim.duration", P(40, 1, 100)},
      {"imm.structure", {{"value", 0}, {"scale", "choice"}, {"choices", L({"axis", "full"})}}}};
  const std::string q4 = "dt^4/4*q^2", q3 = "dt^3/2*q^2", q2 = "dt^2*q^2";
  p["model"] = {
      {"version", 2},
      {"states", L({"x", "vx", "y", "vy"})},
      {"x0", L({"1", "0.5", "-2", "0.2"})},
      {"P0", L({"20", "4", "20", "4"})},
      {"process",
       {{"F", L({L({"1", "dt", "0", "0"}), L({"0", "1", "0", "0"}), L({"0", "0", "1", "dt"}),
                 L({"0", "0", "0", "1"})})},
        {"Q", L({L({q4, q3, "0", "0"}), L({q3, q2, "0", "0"}), L({"0", "0", q4, q3}),
                 L({"0", "0", q3, q2})})}}},
      {"measurements",
       {{"pos",
         {{"roles", L({"zx", "zy"})},
          {"H", L({L({"1", "0", "0", "0"}), L({"0", "0", "1", "0"})})},
          {"R", L({L({"r^2", c}), L({c, "r^2"})})}}}}},
      {"modes",
       {{"list", L({{{"name", "quiet"}}, {{"name", "man"}, {"params", {{"q", "q_man"}}}}})},
        {"markov", {{"stay", 0.9}}},
        {"structure", structure}}}};
  return p;
}

json axis_blocks(bool approximate) {
  return {{"blocks", st_list({st_list({"x", "vx"}), st_list({"y", "vy"})})},
          {"approximate", approximate}};
}

Eigen::MatrixXd F4(double dt) {
  Eigen::MatrixXd F = Eigen::MatrixXd::Identity(4, 4);
  F(0, 1) = F(2, 3) = dt;
  return F;
}
Eigen::MatrixXd Q4(double dt, double q) {
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(4, 4);
  for (int a : {0, 2}) {
    Q(a, a) = std::pow(dt, 4) / 4;
    Q(a, a + 1) = Q(a + 1, a) = std::pow(dt, 3) / 2;
    Q(a + 1, a + 1) = dt * dt;
  }
  return Q * q * q;
}

// The largest |engine − oracle| over the rows, in the form of ../shared/STAGE.md (relative to
// |b| + σ), with the oracle's blocks and R's cross term as given.
double largest_difference(const model::ModelResult& r, const ParamValues& v, const Dataset& d,
                          std::vector<int> blocks, double c) {
  const double dt = v.at("sim.dt");
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2, 4);
  H(0, 0) = H(1, 2) = 1.0;
  Eigen::MatrixXd R(2, 2);
  R << v.at("r") * v.at("r"), c, c, v.at("r") * v.at("r");
  std::vector<oracles::Table2Mode> m{{F4(dt), Q4(dt, v.at("q")), H, R},
                                     {F4(dt), Q4(dt, v.at("q_man")), H, R}};
  Eigen::MatrixXd p(2, 2);
  p << 0.9, 0.1, 0.1, 0.9;
  Eigen::VectorXd x0(4);
  x0 << 1, 0.5, -2, 0.2;
  oracles::ImmTable2 o(m, p, Eigen::VectorXd::Constant(2, 0.5), x0,
                       Eigen::Vector4d(20, 4, 20, 4).asDiagonal());
  o.set_blocks(std::move(blocks));
  double worst = 0.0;
  for (std::size_t k = 0; k < r.steps(); ++k) {
    Eigen::VectorXd z(2);
    z << d.col("zx")[k], d.col("zy")[k];
    const auto row = o.step(k == 0, z);
    for (std::size_t i = 0; i < 4; ++i) {
      const double b = row.x(static_cast<Eigen::Index>(i));
      const double sigma = std::sqrt(r.P[r.diag[i]][k]);
      worst = std::max(worst, std::abs(r.x[i][k] - b) / (std::abs(b) + sigma));
    }
  }
  return worst;
}

struct StructureRun {
  std::unique_ptr<Scenario> s;
  ParamValues v;
  Dataset d;
  std::shared_ptr<const RunResult> r;
};

StructureRun run_structure(const json& preset, double structure_choice = 0) {
  StructureRun out;
  auto s = make_model_scenario(preset, "st.json");
  EXPECT_TRUE(s.ok()) << s.error();
  if (!s.ok()) return out;
  out.s = std::move(*s);
  out.v = out.s->params().defaults();
  out.v["imm.structure"] = structure_choice;
  out.v["c"] = 0.0;
  auto d = out.s->simulate(out.v);
  EXPECT_TRUE(d.ok());
  out.d = *d;
  auto r = out.s->run(out.d, out.v);
  EXPECT_TRUE(r.ok()) << r.error();
  if (r.ok()) out.r = *r;
  return out;
}

TEST(ImmModelStructure, BlocksMixBlockByBlockAsTable2) {
  const StructureRun a = run_structure(two_axis_preset(axis_blocks(false)));
  ASSERT_TRUE(a.r);
  const auto& r = dynamic_cast<const model::ModelResult&>(*a.r);
  EXPECT_LT(largest_difference(r, a.v, a.d, {0, 0, 1, 1}, 0.0), 1e-9);
  // Mixing over the whole vector is a different filter: the blocks matter.
  EXPECT_GT(largest_difference(r, a.v, a.d, {}, 0.0), 1e-6);
}

TEST(ImmModelStructure, ApproximateDropsCrossBlockNoise) {
  StructureRun a = run_structure(two_axis_preset(axis_blocks(true), "c"));
  ASSERT_TRUE(a.r);
  a.v["c"] = 0.4;
  auto r = a.s->run(a.d, a.v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& res = dynamic_cast<const model::ModelResult&>(**r);
  EXPECT_LT(largest_difference(res, a.v, a.d, {0, 0, 1, 1}, 0.0), 1e-9);
}

TEST(ImmModelStructure, AChoiceParameterSelectsTheStructure) {
  const json choice = {{"param", "imm.structure"}, {"axis", axis_blocks(false)}, {"full", "none"}};
  const StructureRun axis = run_structure(two_axis_preset(choice), 0);
  const StructureRun full = run_structure(two_axis_preset(choice), 1);
  ASSERT_TRUE(axis.r && full.r);
  const auto& ra = dynamic_cast<const model::ModelResult&>(*axis.r);
  const auto& rf = dynamic_cast<const model::ModelResult&>(*full.r);
  EXPECT_LT(largest_difference(ra, axis.v, axis.d, {0, 0, 1, 1}, 0.0), 1e-9);
  EXPECT_LT(largest_difference(rf, full.v, full.d, {}, 0.0), 1e-9);
}

std::string error_of(const json& preset) {
  auto s = make_model_scenario(preset, "st.json");
  return s.ok() ? std::string() : s.error();
}

// "detect": the finest blocks that F, Q, P0, H and R keep apart exactly — here the two axes, the
// same filter as declaring them; a model that couples every state is refused, naming the key.
TEST(ImmModelStructure, DetectFindsTheBlocksTheModelKeepsApart) {
  const StructureRun detected = run_structure(two_axis_preset("detect"));
  const StructureRun declared = run_structure(two_axis_preset(axis_blocks(false)));
  ASSERT_TRUE(detected.r && declared.r);
  const auto& rd = dynamic_cast<const model::ModelResult&>(*detected.r);
  const auto& rb = dynamic_cast<const model::ModelResult&>(*declared.r);
  ASSERT_EQ(rd.steps(), rb.steps());
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t k = 0; k < rd.steps(); ++k)
      ASSERT_EQ(rd.x[i][k], rb.x[i][k]) << "state " << i << " row " << k;
  }
  EXPECT_LT(largest_difference(rd, detected.v, detected.d, {0, 0, 1, 1}, 0.0), 1e-9);
  const std::string refused =
      "st.json: model.modes.structure: \"detect\": the model couples all its states (F, Q, P0, "
      "H or R), so there are no blocks to filter apart; declare {\"blocks\", \"approximate\": "
      "true} to drop cross-block terms, or \"none\"";
  EXPECT_EQ(error_of(two_axis_preset("detect", "c")), refused);  // R correlates x and y
  json p = two_axis_preset("detect");
  p["model"]["P0"] = st_list({st_list({"20", "0", "1", "0"}), st_list({"0", "4", "0", "0"}),
                              st_list({"1", "0", "20", "0"}), st_list({"0", "0", "0", "4"})});
  EXPECT_EQ(error_of(p), refused);
  // A mode of the list that couples the axes couples them for every mode.
  p = two_axis_preset("detect");
  p["model"]["modes"]["list"][1]["process"] = p["model"]["process"];
  p["model"]["modes"]["list"][1]["process"]["F"][1][3] = "dt";
  EXPECT_EQ(error_of(p), refused);
  // Blocks of one state each where nothing couples them: three blocks, the filter runs.
  p = two_axis_preset("detect");
  p["model"]["process"]["F"][0][1] = "0";
  p["model"]["process"]["Q"] =
      st_list({st_list({"q^2", "0", "0", "0"}), st_list({"0", "q^2", "0", "0"}),
               st_list({"0", "0", "q^2", "0"}), st_list({"0", "0", "0", "q^2"})});
  auto three = make_model_scenario(p, "st.json");
  ASSERT_TRUE(three.ok()) << three.error();
}

TEST(ImmModelStructure, CoupledBlocksAreRefused) {
  EXPECT_EQ(error_of(two_axis_preset(axis_blocks(false), "c")),
            "st.json: model.modes.structure: model.measurements.pos.R[0][1] couples components "
            "of two blocks (\"approximate\": true drops such entries of Q, R and P0)");
  json p = two_axis_preset(axis_blocks(true));
  p["model"]["process"]["F"][0][2] = "0.1";
  EXPECT_EQ(error_of(p),
            "st.json: model.modes.structure: model.process.F[0][2] couples two blocks: F keeps "
            "the blocks apart");
  p = two_axis_preset(axis_blocks(false));
  p["model"]["measurements"]["pos"]["H"][0][2] = "1";
  EXPECT_EQ(error_of(p),
            "st.json: model.modes.structure: model.measurements.pos.H[0] reads states of two "
            "blocks: a component belongs to one");
  // The continuous form's noise enters through G: one white input driving both axes.
  p = two_axis_preset(axis_blocks(false));
  p["model"]["process"] = {
      {"A", st_list({st_list({"0", "1", "0", "0"}), st_list({"0", "0", "0", "0"}),
                     st_list({"0", "0", "0", "1"}), st_list({"0", "0", "0", "0"})})},
      {"G", st_list({st_list({"0"}), st_list({"1"}), st_list({"0"}), st_list({"1"})})},
      {"Qc", st_list({st_list({"q"})})}};
  EXPECT_EQ(error_of(p),
            "st.json: model.modes.structure: model.process.Qc: G Qc Gᵀ couples the states 'vx' "
            "and 'vy' of two blocks (\"approximate\": true drops such entries of Q, R and P0)");
  p = two_axis_preset({{"blocks", st_list({st_list({"x", "vx"}), st_list({"y"})})}});
  EXPECT_EQ(error_of(p), "st.json: model.modes.structure.blocks: state 'vy' is in no block");
  p = two_axis_preset({{"blocks", st_list({st_list({"x", "vx", "y"}), st_list({"y", "vy"})})}});
  EXPECT_EQ(error_of(p), "st.json: model.modes.structure.blocks[1]: state \"y\" is in two blocks");
}

}  // namespace
}  // namespace kfw
