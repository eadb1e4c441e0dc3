// The expression language of model files: every function and operator means the same to
// muparser (which evaluates) and GiNaC (which differentiates). For each, GiNaC's derivative,
// printed and evaluated by muparser, equals the central difference of muparser's value; values
// equal the C++ library's.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "model/expression.h"

namespace kfw::model {
namespace {

Symbols symbols() {
  Symbols s;
  s.add("q", kParamSymbol);
  s.add("dt", kDtSymbol);
  s.add("t", kTimeSymbol);
  s.add("x", kStateSymbol);
  s.add("y", kStateSymbol);
  s.add("u", kInputSymbol);
  return s;
}

// Evaluates `text` with x, y set (other symbols 0).
double eval(const std::string& text, double x, double y) {
  const Symbols s = symbols();
  std::vector<double> vars(s.names.size(), 0.0);
  vars[3] = x;
  vars[4] = y;
  double out = 0.0;
  ExprGroup g;
  g.add(text, &out);
  EXPECT_TRUE(g.bind(s, vars.data()).ok()) << text;
  g.eval();
  return out;
}

struct ExprCase {
  const char* text;
  double x, y;
  double value;  // from <cmath>
};

double deriv_at(const Expr& d, double x, double y) {
  return d.dep == Dep::kConst ? d.value : eval(d.text, x, y);
}

class Language : public ::testing::TestWithParam<ExprCase> {};

TEST_P(Language, ValueAndDerivativeAgreeInBothLibraries) {
  const ExprCase& c = GetParam();
  const Symbols s = symbols();
  auto e = compile_expr(c.text, "e", s, kAllSymbols, "");
  ASSERT_TRUE(e.ok()) << e.error();
  const double v = eval(c.text, c.x, c.y);
  EXPECT_NEAR(v, c.value, 1e-14 * std::max(1.0, std::fabs(c.value))) << c.text;
  auto d = derivatives(*e, "e", s, {3, 4});
  ASSERT_TRUE(d.ok()) << d.error();
  const double h = 1e-5;
  const double fx = (eval(c.text, c.x + h, c.y) - eval(c.text, c.x - h, c.y)) / (2 * h);
  const double fy = (eval(c.text, c.x, c.y + h) - eval(c.text, c.x, c.y - h)) / (2 * h);
  EXPECT_NEAR(deriv_at((*d)[0], c.x, c.y), fx, 1e-7 * std::max(1.0, std::fabs(fx)))
      << c.text << " d/dx = " << (*d)[0].text;
  EXPECT_NEAR(deriv_at((*d)[1], c.x, c.y), fy, 1e-7 * std::max(1.0, std::fabs(fy)))
      << c.text << " d/dy = " << (*d)[1].text;
}

const double kX = 0.3, kY = -0.7;

INSTANTIATE_TEST_SUITE_P(
    Functions, Language,
    ::testing::Values(
        ExprCase{"sin(x)", kX, kY, std::sin(kX)}, ExprCase{"cos(x)", kX, kY, std::cos(kX)},
        ExprCase{"tan(x)", kX, kY, std::tan(kX)}, ExprCase{"asin(x)", kX, kY, std::asin(kX)},
        ExprCase{"acos(x)", kX, kY, std::acos(kX)}, ExprCase{"atan(x)", kX, kY, std::atan(kX)},
        ExprCase{"atan2(y, x)", kX, kY, std::atan2(kY, kX)},
        ExprCase{"atan2(y, x)", -kX, 0.1, std::atan2(0.1, -kX)},
        ExprCase{"sinh(x)", kX, kY, std::sinh(kX)}, ExprCase{"cosh(x)", kX, kY, std::cosh(kX)},
        ExprCase{"tanh(x)", kX, kY, std::tanh(kX)}, ExprCase{"exp(x)", kX, kY, std::exp(kX)},
        ExprCase{"log(x)", kX, kY, std::log(kX)}, ExprCase{"sqrt(x)", kX, kY, std::sqrt(kX)},
        ExprCase{"abs(y)", kX, kY, std::fabs(kY)}, ExprCase{"abs(x)", kX, kY, kX},
        ExprCase{"pow(x, y)", kX, kY, std::pow(kX, kY)}, ExprCase{"min(x, y)", kX, kY, kY},
        ExprCase{"max(x, y)", kX, kY, kX}, ExprCase{"min(x, y)", kY, kX, kY},
        ExprCase{"max(x^2, y)", kX, kY, kX* kX}, ExprCase{"pi*x", kX, kY, std::numbers::pi* kX}),
    [](const ::testing::TestParamInfo<ExprCase>& c) { return "f" + std::to_string(c.index); });

INSTANTIATE_TEST_SUITE_P(
    Operators, Language,
    ::testing::Values(ExprCase{"-x^2", kX, kY, -kX* kX},
                      ExprCase{"2^(-x) + 1", kX, kY, std::pow(2.0, -kX) + 1},
                      ExprCase{"x^(-1) - y", kX, kY, 1.0 / kX - kY},
                      ExprCase{"x/2/y", kX, kY, kX / 2 / kY},
                      ExprCase{"x - y - 1", kX, kY, kX - kY - 1},
                      ExprCase{"2*(-x^2) + y", kX, kY, -2 * kX* kX + kY},
                      ExprCase{"1.5e-3*x + .5*y", kX, kY, 1.5e-3 * kX + 0.5 * kY},
                      ExprCase{"(x + y)^3/3", kX, kY, std::pow(kX + kY, 3) / 3},
                      ExprCase{"x*y*exp(-x*y)", kX, kY, kX* kY* std::exp(-kX* kY)},
                      ExprCase{"sqrt(x^2 + y^2)", kX, kY, std::hypot(kX, kY)}),
    [](const ::testing::TestParamInfo<ExprCase>& c) { return "op" + std::to_string(c.index); });

TEST(Expression, DependencyClasses) {
  const Symbols s = symbols();
  auto dep = [&](const char* text) {
    auto e = compile_expr(text, "e", s, kAllSymbols, "");
    EXPECT_TRUE(e.ok()) << e.error();
    return e.ok() ? e->dep : Dep::kState;
  };
  EXPECT_EQ(dep("2*3 + pi"), Dep::kConst);
  EXPECT_EQ(dep("q^2"), Dep::kParam);
  EXPECT_EQ(dep("q*dt"), Dep::kDt);
  EXPECT_EQ(dep("q*t"), Dep::kStep);
  EXPECT_EQ(dep("u*dt"), Dep::kStep);
  EXPECT_EQ(dep("x*q*dt"), Dep::kState);
  auto c = compile_expr("2*3 + 1", "e", s, kAllSymbols, "");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->value, 7.0);
}

TEST(Expression, DerivativesOfConstantsAndDependencies) {
  const Symbols s = symbols();
  auto e = compile_expr("x*q + dt*y + 3*x", "e", s, kAllSymbols, "");
  ASSERT_TRUE(e.ok());
  auto d = derivatives(*e, "e", s, {3, 4});
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ((*d)[0].dep, Dep::kParam);  // q + 3
  EXPECT_EQ((*d)[1].dep, Dep::kDt);     // dt
  auto lin = compile_expr("x + 2*y", "e", s, kAllSymbols, "");
  ASSERT_TRUE(lin.ok());
  auto dl = derivatives(*lin, "e", s, {3, 4});
  ASSERT_TRUE(dl.ok());
  EXPECT_EQ((*dl)[0].dep, Dep::kConst);
  EXPECT_EQ((*dl)[0].value, 1.0);
  EXPECT_EQ((*dl)[1].value, 2.0);
}

// A sign right after an operator: muparser reads 2*-x + y as −2x + y, GiNaC as −2(x + y).
TEST(Expression, SignAfterAnOperatorIsRefused) {
  const Symbols s = symbols();
  for (const char* text : {"2*-x + y", "x^-1", "x + +y", "x - -y", "x/-y"}) {
    auto e = compile_expr(text, "e", s, kAllSymbols, "");
    ASSERT_FALSE(e.ok()) << text;
    EXPECT_NE(e.error().find("a sign right after an operator"), std::string::npos) << e.error();
  }
  for (const char* text : {"-x + y", "(-x)*2", "atan2(-y, x)", "1e-3*x", "+x"})
    EXPECT_TRUE(compile_expr(text, "e", s, kAllSymbols, "").ok()) << text;
}

TEST(Expression, SameFunctionIsSymbolic) {
  const Symbols s = symbols();
  auto a = compile_expr("q*dt^2/2", "a", s, kAllSymbols, "");
  auto b = compile_expr("0.5*dt*q*dt", "b", s, kAllSymbols, "");
  auto c = compile_expr("q*dt^2", "c", s, kAllSymbols, "");
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_TRUE(same_function(*a, *b, s));
  EXPECT_FALSE(same_function(*a, *c, s));
}

TEST(Expression, ReservedNamesAndIdentifiers) {
  for (const char* r : {"t", "dt", "pi", "sin", "atan2", "min"})
    EXPECT_TRUE(is_reserved_name(r)) << r;
  EXPECT_FALSE(is_reserved_name("theta"));
  EXPECT_TRUE(is_identifier("P0_theta"));
  EXPECT_FALSE(is_identifier("sim.seed"));
  EXPECT_FALSE(is_identifier("2x"));
}

// The README's function table lists exactly the language's functions.
TEST(Expression, ReadmeListsEveryFunction) {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/README.md");
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string readme = ss.str();
  for (const auto& f : language_functions()) {
    std::string call = "`" + std::string(f.name) + "(";
    EXPECT_NE(readme.find(call), std::string::npos) << f.name;
  }
}

}  // namespace
}  // namespace kfw::model
