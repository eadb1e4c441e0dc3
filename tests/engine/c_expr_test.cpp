// The C export's expression writer (engine/codegen/c_expr.h): numbers as exact C literals, the
// language's operators and functions as C, repeated sub-trees computed once, text for C comments.
#include "codegen/c_expr.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "codegen/c_export.h"
#include "codegen/c_export_detail.h"

namespace kfw::codegen {
namespace {

std::string c_expr_symbol(const std::string& name) {
  return name == "x" ? "x[0]" : "par_" + name;
}

TEST(CExpr, NumbersAreExactDoubleLiterals) {
  EXPECT_EQ(c_number(4.0, false), "4.0");  // 1/2 stays a division of doubles
  EXPECT_EQ(c_number(0.1, false), "0.1");
  EXPECT_EQ(c_number(-2.5, false), "(-2.5)");
  EXPECT_EQ(c_number(0.1, true), "0.1f");
  EXPECT_EQ(c_number(1e300, true), "HUGE_VALF");
  for (double v : {1.0 / 3.0, 6.02214076e23, 5e-324, 123456789.123456789}) {
    const std::string s = c_number(v, false);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
}

TEST(CExpr, OperatorsFunctionsAndPowersAsC) {
  const auto c = [](const std::string& text, std::set<std::string>* helpers = nullptr) {
    CExprSet set(false, c_expr_symbol);
    EXPECT_TRUE(set.add(text, "k").ok());
    std::vector<std::string> out;
    EXPECT_EQ(set.emit("  ", out), "");  // nothing repeated
    if (helpers) *helpers = set.helpers();
    return out.at(0);
  };
  EXPECT_EQ(c("1/2*x^2 - -(x)"), "1.0 / 2.0 * kfw_sq(x[0]) - (-x[0])");
  std::set<std::string> h;
  EXPECT_EQ(c("atan2(x, q) + abs(x)^3 + min(x, 1)", &h),
            "atan2(x[0], par_q) + kfw_cube(fabs(x[0])) + fmin(x[0], 1.0)");
  EXPECT_EQ(h, (std::set<std::string>{"kfw_cube"}));
  EXPECT_EQ(c("-x^2 + x^0.5 + x^q + sinc(x)", &h),
            "-kfw_sq(x[0]) + sqrt(x[0]) + pow(x[0], par_q) + kfw_sinc(x[0])");
  EXPECT_EQ(h, (std::set<std::string>{"kfw_sinc", "kfw_sq"}));
}

TEST(CExpr, RepeatedSubTreesAreComputedOnce) {
  CExprSet set(true, c_expr_symbol);
  ASSERT_TRUE(set.add("sin(x*q)*(x*q)", "a").ok());
  ASSERT_TRUE(set.add("cos(x*q) + sin(x*q)", "b").ok());
  std::vector<std::string> out;
  const std::string temps = set.emit("  ", out);
  EXPECT_EQ(temps,
            "  const float c0 = x[0] * par_q;\n"
            "  const float c1 = sinf(c0);\n");
  EXPECT_EQ(out[0], "c1 * c0");
  EXPECT_EQ(out[1], "cosf(c0) + c1");
}

TEST(CExpr, ASumKeepsItsOrderOfEvaluation) {
  CExprSet set(false, c_expr_symbol);
  ASSERT_TRUE(set.add("a - (b - c) + (d + e)", "k").ok());
  std::vector<std::string> out;
  set.emit("", out);
  EXPECT_EQ(out[0], "par_a - (par_b - par_c) + (par_d + par_e)");
}

TEST(CExpr, AnUnknownFunctionIsRefusedWithItsKey) {
  CExprSet set(false, c_expr_symbol);
  ASSERT_TRUE(set.add("erf(x)", "model.process.f[0]").ok());
  std::vector<std::string> out;
  EXPECT_THROW(set.emit("", out), std::runtime_error);
  const auto bad = set.add("x +", "model.process.f[1]");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("model.process.f[1]"), std::string::npos) << bad.error();
}

TEST(CExpr, TextInACommentCannotEndIt) {
  const std::string t = detail::comment_text("a */ b /* c\nd");
  EXPECT_EQ(t.find("*/"), std::string::npos) << t;
  EXPECT_EQ(t.find("/*"), std::string::npos) << t;
  EXPECT_EQ(t.find('\n'), std::string::npos) << t;
}

TEST(CExpr, PrefixesAreCIdentifiers) {
  EXPECT_EQ(default_prefix("presets/models/cv1d.json"), "cv1d");
  EXPECT_EQ(default_prefix("/x/9 lives-2.json"), "_9_lives_2");
  EXPECT_TRUE(is_c_identifier("range_bearing"));
  EXPECT_FALSE(is_c_identifier("int"));
  EXPECT_FALSE(is_c_identifier("9a"));
  EXPECT_FALSE(is_c_identifier("a-b"));
}

}  // namespace
}  // namespace kfw::codegen
