// Issue 27, the expression language of model files (format version 2): sub-expressions (named,
// usable everywhere, expanded into the expressions that use them), sinc for removable
// singularities, and the continuous nonlinear process ẋ = f(x, u, t) — RK4 for the mean, F the
// exact Jacobian of the RK4 step map, Q by Van Loan on (A(x⁻), G Qc Gᵀ). The Van der Pol model
// file is checked against an EKF written here from the equations (Eigen's own matrix exponential
// for Van Loan), to 1e-9 in the form of ../shared/STAGE.md.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/scenario.h"
#include "model/expression.h"
#include "model/model_expressions.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw::model {
namespace {

Symbols base_symbols() {
  Symbols s;
  s.add("q", kParamSymbol);
  s.add("dt", kDtSymbol);
  s.add("t", kTimeSymbol);
  s.add("x", kStateSymbol);
  s.add("y", kStateSymbol);
  return s;
}

double eval_at(const Expr& e, const Symbols& s, double x, double y, double q = 0.0) {
  if (e.dep == Dep::kConst) return e.value;
  std::vector<double> vars(s.names.size(), 0.0);
  vars[0] = q;
  vars[3] = x;
  vars[4] = y;
  double out = 0.0;
  ExprGroup g;
  g.add(e.text, &out);
  EXPECT_TRUE(g.bind(s, vars.data()).ok()) << e.text;
  g.eval();
  return out;
}

// ---- sinc ------------------------------------------------------------------------------------

TEST(ModelWorldSinc, ValueIsSinOverXAndOneAtZero) {
  EXPECT_EQ(sinc(0.0), 1.0);
  for (double x : {1e-300, 1e-9, 0.3, -2.0, 40.0})
    EXPECT_NEAR(sinc(x), std::sin(x) / x, 1e-16) << x;
  const Symbols s = base_symbols();
  auto e = compile_expr("sinc(x)", "e", s, kAllSymbols, "");
  ASSERT_TRUE(e.ok()) << e.error();
  EXPECT_DOUBLE_EQ(eval_at(*e, s, 0.7, 0.0), std::sin(0.7) / 0.7);
  EXPECT_EQ(eval_at(*e, s, 0.0, 0.0), 1.0);
}

// GiNaC's derivative (printed as dsinc, evaluated by muparser) against a central difference of
// muparser's value, on both sides of the series/closed-form switch at |x| = 0.01 and at 0.
TEST(ModelWorldSinc, DerivativeAgreesInBothLibraries) {
  const Symbols s = base_symbols();
  auto e = compile_expr("sinc(x*y)", "e", s, kAllSymbols, "");
  ASSERT_TRUE(e.ok()) << e.error();
  auto d = derivatives(*e, "e", s, {3, 4});
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_NE((*d)[0].text.find("dsinc"), std::string::npos) << (*d)[0].text;
  for (double x : {0.0, 1e-6, 0.0099, 0.0999, 0.1001, 0.5, -3.0}) {
    const double y = 1.0, h = 1e-6;
    const double fd = (eval_at(*e, s, x + h, y) - eval_at(*e, s, x - h, y)) / (2 * h);
    EXPECT_NEAR(eval_at((*d)[0], s, x, y), fd, 1e-9) << x;
    // The closed form cancels near 0; there the series to x⁹ (next term below 1e-22).
    const double x2 = x * x;
    const double exact =
        std::fabs(x) < 0.1
            ? x * (-1.0 / 3 +
                   x2 * (1.0 / 30 + x2 * (-1.0 / 840 + x2 * (1.0 / 45360 - x2 / 3991680))))
            : (std::cos(x) - std::sin(x) / x) / x;
    EXPECT_NEAR(dsinc(x), exact, 1e-17 + 1e-13 * std::fabs(exact)) << x;
  }
}

// The coordinated-turn position step v/ω·(sin(ψ + ω dt) − sin ψ), written with sinc, is finite and
// right at ω = 0 (straight line, v dt cos ψ) and equals the closed form elsewhere.
TEST(ModelWorldSinc, CoordinatedTurnStepHasNoSingularity) {
  Symbols s;
  s.add("dt", kDtSymbol);
  s.add("v", kStateSymbol);
  s.add("psi", kStateSymbol);
  s.add("w", kStateSymbol);
  auto e = compile_expr("v*dt*cos(psi + w*dt/2)*sinc(w*dt/2)", "e", s, kAllSymbols, "");
  ASSERT_TRUE(e.ok()) << e.error();
  auto value = [&](double v, double psi, double w) {
    std::vector<double> vars = {0.5, v, psi, w};
    double out = 0.0;
    ExprGroup g;
    g.add(e->text, &out);
    EXPECT_TRUE(g.bind(s, vars.data()).ok());
    g.eval();
    return out;
  };
  EXPECT_NEAR(value(10.0, 0.3, 0.0), 10.0 * 0.5 * std::cos(0.3), 1e-15);
  const double w = 0.2;
  EXPECT_NEAR(value(10.0, 0.3, w), 10.0 / w * (std::sin(0.3 + w * 0.5) - std::sin(0.3)), 1e-13);
}

// ---- sub-expressions -------------------------------------------------------------------------

Expected<Symbols> with_subs(const std::string& json_text) {
  Symbols s = base_symbols();
  if (auto st = parse_expressions(nlohmann::json::parse(json_text), "m.json", s); !st) {
    return st.err();
  }
  return s;
}

TEST(ModelWorldSubExpressions, ExpandIntoTheirUsersInAnyOrder) {
  // r uses r2, declared after it (JSON objects have no order): r2 is defined first.
  auto s = with_subs(R"J({"r": "sqrt(r2)", "r2": "x^2 + y^2", "two": "2"})J");
  ASSERT_TRUE(s.ok()) << s.error();
  auto e = compile_expr("two*r", "e", *s, kAllSymbols, "");
  ASSERT_TRUE(e.ok()) << e.error();
  EXPECT_EQ(e->dep, Dep::kState);
  EXPECT_EQ(e->uses, KindMask{kStateSymbol});
  EXPECT_DOUBLE_EQ(eval_at(*e, *s, 3.0, 4.0), 10.0);
  auto c = compile_expr("two*two + q", "c", *s, kAllSymbols, "");
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->dep, Dep::kParam);
  auto k = compile_expr("two*3", "k", *s, kAllSymbols, "");
  ASSERT_TRUE(k.ok()) << k.error();
  EXPECT_EQ(k->dep, Dep::kConst);
  EXPECT_EQ(k->value, 6.0);  // folded through the expansion, not with the symbol at 0
  // The derivative goes through the sub-expressions: ∂(2 r)/∂x = 2 x / r.
  auto d = derivatives(*e, "e", *s, {3});
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_NEAR(eval_at((*d)[0], *s, 3.0, 4.0), 2.0 * 3.0 / 5.0, 1e-15);
}

TEST(ModelWorldSubExpressions, AreRefusedWhereTheirSymbolsAre) {
  auto s = with_subs(R"J({"r": "sqrt(x^2 + y^2)"})J");
  ASSERT_TRUE(s.ok()) << s.error();
  auto e = compile_expr("q*r", "model.process.F[0][0]", *s, kParamSymbol | kDtSymbol, "F's");
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error(),
            "model.process.F[0][0]: sub-expression 'r' uses state 'x', which cannot be used here "
            "(F's) at position 3: \"q*r\"");
}

TEST(ModelWorldSubExpressions, CyclesNamesAndSizesAreRefused) {
  auto cycle = with_subs(R"J({"a": "b + 1", "b": "2*a"})J");
  ASSERT_FALSE(cycle.ok());
  EXPECT_EQ(cycle.error(), "m.json: model.expressions.a: defined in terms of itself (a → b → a)");
  auto self = with_subs(R"J({"a": "a + 1"})J");
  ASSERT_FALSE(self.ok());
  EXPECT_EQ(self.error(), "m.json: model.expressions.a: defined in terms of itself (a → a)");
  auto clash = with_subs(R"J({"x": "1"})J");
  ASSERT_FALSE(clash.ok());
  EXPECT_EQ(clash.error(),
            "m.json: model.expressions.x: 'x' is already a parameter, state or input");
  auto reserved = with_subs(R"J({"dsinc": "1"})J");
  ASSERT_FALSE(reserved.ok());
  EXPECT_EQ(reserved.error(), "m.json: model.expressions.dsinc: 'dsinc' is reserved");
  auto bad = with_subs(R"J({"a": "x +* 2"})J");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("m.json: model.expressions.a: "), std::string::npos) << bad.error();
  // Each link uses the previous twice: the expansion doubles and is refused, not built.
  std::string chain = R"J({"a0": "x")J";
  for (int i = 1; i <= 20; ++i)
    chain += ", \"a" + std::to_string(i) + "\": \"a" + std::to_string(i - 1) + " + a" +
             std::to_string(i - 1) + "\"";
  auto big = with_subs(chain + "}");
  // A chain 101 deep is refused (a 1000-deep chain took 41 s to load).
  std::string deep = R"J({"c0": "x")J";
  for (int i = 1; i <= 100; ++i)
    deep += ", \"c" + std::to_string(i) + "\": \"c" + std::to_string(i - 1) + " + 1\"";
  auto too_deep = with_subs(deep + "}");
  ASSERT_FALSE(too_deep.ok());
  EXPECT_NE(too_deep.error().find("sub-expressions nested more than 100 deep"), std::string::npos)
      << too_deep.error();
  deep = R"J({"c0": "x")J";
  for (int i = 1; i < 100; ++i)
    deep += ", \"c" + std::to_string(i) + "\": \"c" + std::to_string(i - 1) + " + 1\"";
  EXPECT_TRUE(with_subs(deep + "}").ok());
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().find("its sub-expressions expand to"), std::string::npos) << big.error();
}

// ---- model files -----------------------------------------------------------------------------

const std::string kVdpPath = KFW_SOURCE_DIR "/presets/models/van_der_pol.json";

nlohmann::json vdp_json() {
  std::ifstream in(kVdpPath);
  return nlohmann::json::parse(in);
}

TEST(ModelWorldFormat, VersionTwoKeysNeedVersionTwo) {
  nlohmann::json j = vdp_json();
  j["model"]["version"] = 1;
  auto s = make_model_scenario(j, "vdp.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(), "vdp.json: model.expressions: a version-2 key: set \"version\": 2");
  j["model"]["version"] = 3;
  s = make_model_scenario(j, "vdp.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(), "vdp.json: model.version: is 3, this build reads versions 1 to 2");
  j["model"]["version"] = 2;
  j["model"]["process"]["xdot"][0] = "v*dt";
  s = make_model_scenario(j, "vdp.json");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("model.process.xdot[0]: dt cannot be used here"), std::string::npos)
      << s.error();
}

// The Van der Pol EKF, written from the equations: ẋ = v, v̇ = μ(1 − x²)v − x + w.
struct VdpEkf {
  double mu, q, r, h_max;
  Eigen::Vector2d x;
  Eigen::Matrix2d P;

  Eigen::Vector2d f(const Eigen::Vector2d& s) const {
    return {s(1), mu * (1 - s(0) * s(0)) * s(1) - s(0)};
  }
  Eigen::Matrix2d A(const Eigen::Vector2d& s) const {
    Eigen::Matrix2d a;
    a << 0, 1, -2 * mu * s(0) * s(1) - 1, mu * (1 - s(0) * s(0));
    return a;
  }
  // RK4 over dt in ceil(dt/h) sub-steps; J: the Jacobian of the whole step map.
  void rk4(double dt, Eigen::Vector2d& xo, Eigen::Matrix2d& J) const {
    const int steps = h_max > 0 ? std::max(1, static_cast<int>(std::ceil(dt / h_max - 1e-9))) : 1;
    const double h = dt / steps;
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    xo = x;
    J = I;
    for (int i = 0; i < steps; ++i) {
      const Eigen::Vector2d k1 = f(xo), k2 = f(xo + h / 2 * k1), k3 = f(xo + h / 2 * k2),
                            k4 = f(xo + h * k3);
      const Eigen::Matrix2d D1 = A(xo), D2 = A(xo + h / 2 * k1) * (I + h / 2 * D1),
                            D3 = A(xo + h / 2 * k2) * (I + h / 2 * D2),
                            D4 = A(xo + h * k3) * (I + h * D3);
      xo += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      J = ((I + h / 6 * (D1 + 2 * D2 + 2 * D3 + D4)) * J).eval();
    }
  }
  void predict(double dt) {
    Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
    const Eigen::Matrix2d a = A(x);
    Eigen::Matrix2d gqg = Eigen::Matrix2d::Zero();
    gqg(1, 1) = q;
    C.topLeftCorner<2, 2>() = -a * dt;
    C.topRightCorner<2, 2>() = gqg * dt;
    C.bottomRightCorner<2, 2>() = a.transpose() * dt;
    const Eigen::Matrix4d E = C.exp();
    const Eigen::Matrix2d Fq = E.bottomRightCorner<2, 2>().transpose();
    Eigen::Matrix2d Q = Fq * E.topRightCorner<2, 2>();
    Q = 0.5 * (Q + Q.transpose()).eval();
    Eigen::Vector2d xn;
    Eigen::Matrix2d F;
    rk4(dt, xn, F);
    x = xn;
    P = F * P * F.transpose() + Q;
  }
  void update(double z) {
    const Eigen::RowVector2d H(1, 0);
    const double S = (H * P * H.transpose())(0, 0) + r;
    const Eigen::Vector2d K = P * H.transpose() / S;
    x += K * (z - x(0));
    const Eigen::Matrix2d IKH = Eigen::Matrix2d::Identity() - K * H;
    P = IKH * P * IKH.transpose() + K * r * K.transpose();
  }
};

void expect_vdp_equal(const ParamValues& v, const std::string& what) {
  SCOPED_TRACE(what);
  auto s = make_model_scenario(vdp_json(), kVdpPath);
  ASSERT_TRUE(s.ok()) << s.error();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& m = dynamic_cast<const ModelResult&>(**r);
  const auto& t = d->col("t");
  const auto& z = d->col("z");
  VdpEkf ekf{v.at("mu"), v.at("q"), v.at("sigma_x") * v.at("sigma_x"), v.at("h"), {}, {}};
  ekf.x << v.at("x_init"), 0.0;
  ekf.P = Eigen::Vector2d(v.at("P0_x"), v.at("P0_v")).asDiagonal();
  ASSERT_GT(m.steps(), 100u);
  double worst = 0.0;
  for (std::size_t k = 0; k < m.steps(); ++k) {
    if (k > 0) ekf.predict(t[k] - t[k - 1]);
    ekf.update(z[k]);
    for (int i = 0; i < 2; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const double sigma = std::sqrt(ekf.P(i, i));
      const double err = std::fabs(m.x[ui][k] - ekf.x(i)) / (std::fabs(ekf.x(i)) + sigma);
      const double perr =
          std::fabs(m.P[m.cov_index(ui, ui)][k] - ekf.P(i, i)) / std::fabs(ekf.P(i, i));
      worst = std::max({worst, err, perr});
    }
    const double pc =
        std::fabs(m.P[m.cov_index(0, 1)][k] - ekf.P(0, 1)) / std::sqrt(ekf.P(0, 0) * ekf.P(1, 1));
    worst = std::max(worst, pc);
  }
  EXPECT_LE(worst, 1e-9);
  std::printf("[ %s ] largest difference from the EKF written here: %.2e\n", what.c_str(), worst);
}

TEST(ModelWorldContinuous, VanDerPolEqualsAnIndependentRk4Ekf) {
  auto s = make_model_scenario(vdp_json(), kVdpPath);
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  expect_vdp_equal(v, "4 sub-steps per interval");
  v["h"] = 0.0;
  expect_vdp_equal(v, "one RK4 step per interval");
  v["h"] = 0.03;  // 0.1/0.03: 4 sub-steps of 0.025
  v["mu"] = 3.0;
  v["sim.seed"] = 7;
  expect_vdp_equal(v, "μ = 3, seed 7");
}

TEST(ModelWorldContinuous, UkfAndSimulationRunAndAreConsistent) {
  auto s = make_model_scenario(vdp_json(), kVdpPath);
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  double nees = 0.0;
  int runs = 0;
  for (const char* filter : {"ekf", "ukf"}) {
    ASSERT_TRUE((*s)->params().apply_assignment(std::string("filter=") + filter, v).ok());
    for (int seed = 1; seed <= 10; ++seed) {
      v["sim.seed"] = seed;
      auto d = (*s)->simulate(v);
      ASSERT_TRUE(d.ok()) << d.error();
      auto r = (*s)->run(*d, v);
      ASSERT_TRUE(r.ok()) << r.error();
      const auto& m = dynamic_cast<const ModelResult&>(**r);
      double sum = 0.0;
      for (double e : m.nees)
        sum += e;
      nees += sum / static_cast<double>(m.steps());
      ++runs;
    }
  }
  // 20 runs of 201 steps, 2 dof: the mean NEES of a consistent filter is near 2.
  EXPECT_GT(nees / runs, 1.5);
  EXPECT_LT(nees / runs, 2.6);
  std::printf("mean NEES over %d runs (EKF and UKF, seeds 1..10): %.3f (2 dof)\n", runs,
              nees / runs);
}

TEST(ModelWorldContinuous, SubstepIsChecked) {
  nlohmann::json j = vdp_json();
  j["parameters"]["h"]["min"] = -1.0;
  j["parameters"]["h"]["value"] = -0.5;
  auto s = make_model_scenario(j, "vdp.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(),
            "vdp.json: model.process.substep: -0.5 at the parameters' values; expected a sub-step "
            "≥ 0 s (0: one RK4 step per interval)");
  // A sub-step far below the data's interval is refused when the interval is known.
  j = vdp_json();
  j["parameters"]["h"]["min"] = 1e-9;
  j["parameters"]["h"]["value"] = 1e-9;
  auto tiny = make_model_scenario(j, "vdp.json");
  ASSERT_FALSE(tiny.ok());  // checked at load at sim.dt (exit 2, file and key named)
  EXPECT_EQ(tiny.error(),
            "vdp.json: model.process.substep: needs 100000000 RK4 sub-steps per interval (at most "
            "100000) at dt = 0.1 s (sim.dt)");
}

}  // namespace
}  // namespace kfw::model
