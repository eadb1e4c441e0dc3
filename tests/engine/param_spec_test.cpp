#include "core/param_spec.h"

#include <gtest/gtest.h>

#include <cmath>

namespace kfw {
namespace {

ParamTable table() {
  return ParamTable({{"Q", "Q", "(deg/s)²", 1e-6, 1e6, 1.0, Scale::kLog},
                     {"m", "m", "", 1, 100, 1, Scale::kInteger},
                     {"mode", "mode", "", 0, 2, 0, Scale::kChoice, "", "", 0, {"AS", "SC", "SI"}}});
}

TEST(ParamTable, DefaultsAndChecks) {
  const auto t = table();
  auto v = t.defaults();
  EXPECT_EQ(v.size(), 3u);
  EXPECT_TRUE(t.check(v).ok());
  EXPECT_FALSE(t.check("Q", 2e6).ok());
  EXPECT_NE(t.check("Q", -1).error().find("'Q' = -1 is out of range [1e-06, 1000000] (deg/s)²"),
            std::string::npos)
      << t.check("Q", -1).error();
  EXPECT_FALSE(t.check("m", 2.5).ok());
  EXPECT_FALSE(t.check("Q", std::nan("")).ok());
  EXPECT_NE(t.check("nope", 1).error().find("unknown parameter 'nope'"), std::string::npos);
  v.erase("m");
  EXPECT_NE(t.check(v).error().find("'m' has no value"), std::string::npos);
}

TEST(ParamTable, Assignments) {
  const auto t = table();
  auto v = t.defaults();
  EXPECT_TRUE(t.apply_assignment("Q=256", v).ok());
  EXPECT_EQ(v["Q"], 256);
  EXPECT_TRUE(t.apply_assignment("mode=SI", v).ok());
  EXPECT_EQ(v["mode"], 2);
  EXPECT_EQ(t.format("mode", v["mode"]), "SI");
  EXPECT_FALSE(t.apply_assignment("mode=XX", v).ok());
  EXPECT_FALSE(t.apply_assignment("Q=abc", v).ok());
  EXPECT_FALSE(t.apply_assignment("Q=1e7", v).ok());
  EXPECT_FALSE(t.apply_assignment("Q", v).ok());
  EXPECT_FALSE(t.apply_assignment("Z=1", v).ok());
  EXPECT_EQ(v["Q"], 256);  // failed assignments change nothing
}

TEST(ParseDouble, StrictWholeString) {
  double x = 0;
  EXPECT_TRUE(parse_double(" 1e-3 ", x));
  EXPECT_DOUBLE_EQ(x, 1e-3);
  EXPECT_FALSE(parse_double("1e-3x", x));
  EXPECT_FALSE(parse_double("", x));
  EXPECT_FALSE(parse_double("nan", x));
  EXPECT_FALSE(parse_double("inf", x));
}

}  // namespace
}  // namespace kfw
