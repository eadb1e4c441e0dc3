// Missing versus invalid data (README "Missing and invalid data"), one case per rule: empty and
// NaN cells are missing samples; inf, overflow and text are invalid with FILE:LINE:COL; a required
// column with no value is invalid; only columns bound to a role are validated; a run that turns
// non-finite stops with the step and time (exit code 1).
#include <gtest/gtest.h>

#include <fstream>

#include "core/dataset.h"
#include "core/scenario.h"
#include "data/csv.h"
#include "document/preset.h"
#include "document/workspace.h"

namespace kfw {
namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Seed 000's model file (columns t, gyro, angle; truth optional).
std::shared_ptr<const Scenario> policy_heli() {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  EXPECT_TRUE(p.ok()) << p.error();
  return p.ok() ? p->instance : nullptr;
}

// Each test writes its own file: ctest runs the tests of this binary in parallel processes.
Expected<Dataset> load(const std::string& text, const Mapping& m = {}) {
  auto s = policy_heli();
  if (!s) return Error{"presets/helicopter.json does not load"};
  const std::string name =
      std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_policy.csv";
  return load_dataset_file(*s, write(name, text), m);
}

struct PolicyCase {
  const char* name;
  std::string csv;
  int exit_code;         // 0: loads
  const char* fragment;  // in the message
};

TEST(DataPolicy, TableOfRules) {
  const PolicyCase cases[] = {
      {"empty cell is missing", "t,gyro,angle\n0,1,\n0.02,,2\n0.04,1,2\n", 0, ""},
      {"NaN words are missing", "t,gyro,angle\n0,NaN,1\n0.02,nan,NA\n0.04,1,2\n", 0, ""},
      {"inf is invalid", "t,gyro,angle\n0,1,2\n0.02,inf,2\n", 2,
       "policy.csv:3:6: column 'gyro': infinite value"},
      {"overflow is invalid", "t,gyro,angle\n0,1,2\n0.02,1,1e999\n", 2,
       "policy.csv:3:8: column 'angle': '1e999' overflows a double"},
      {"text is invalid", "t,gyro,angle\n0,1,2\n0.02,x,2\n", 2,
       "policy.csv:3:6: column 'gyro': 'x' is not a number"},
      {"required column with no value", "t,gyro,angle\n0,1,\n0.02,2,NaN\n", 2,
       "column 'angle' has no value"},
      {"time on every row", "t,gyro,angle\n0,1,2\n,1,2\n", 2,
       "policy.csv:3:1: column 't' is empty"},
      {"unbound column is ignored", "t,gyro,angle,notes\n0,1,2,hello\n0.02,1,2,inf\n", 0, ""},
      {"infinite sample period", "t,gyro,angle\n-1e308,1,2\n1e308,1,2\n", 2, "overflows a double"},
      {"binary file", std::string("t,gyro,angle\n0,1,2\n\0\1\2,3\n", 25), 2, "not a text file"},
      {"huge token is not echoed", "t,gyro,angle\n0," + std::string(100000, 'x') + ",2\n", 2, "…"},
  };
  for (const auto& c : cases) {
    auto d = load(c.csv);
    if (c.exit_code == 0) {
      EXPECT_TRUE(d.ok()) << c.name << ": " << d.error();
      continue;
    }
    ASSERT_FALSE(d.ok()) << c.name;
    EXPECT_EQ(d.exit_code(), c.exit_code) << c.name;
    EXPECT_NE(d.error().find(c.fragment), std::string::npos) << c.name << ": " << d.error();
    EXPECT_LT(d.error().size(), 400u) << c.name;
    EXPECT_EQ(d.error().find('\n'), std::string::npos) << c.name;
  }
}

TEST(DataPolicy, MappingNamesOtherColumnsAndConvertsUnits) {
  Mapping m;
  m["t"] = {"time_ms", "ms"};
  m["gyro"] = {"omega", "rad/s"};
  m["angle"] = {"roll"};
  auto d = load("time_ms,omega,roll\n0,0.1,2\n20,0.2,3\n", m);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_DOUBLE_EQ(d->col("t")[1], 0.02);
  EXPECT_NEAR(d->col("gyro")[1], 0.2 * 180.0 / 3.14159265358979323846, 1e-12);
  EXPECT_EQ(d->col("angle")[0], 2.0);
  m["gyro"].column = "nope";
  auto bad = load("time_ms,omega,roll\n0,0.1,2\n20,0.2,3\n", m);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("mapped column 'nope' (for 'gyro')"), std::string::npos);
}

TEST(DataPolicy, ARunThatTurnsNonFiniteStopsWithStepAndTime) {
  auto s = policy_heli();
  ASSERT_TRUE(s);
  std::string csv = "t,gyro,angle\n";
  for (int k = 0; k < 200; ++k) {
    csv += std::to_string(0.02 * k) + "," + (k == 100 ? "1e308" : "1") + ",0\n";
  }
  auto d = read_csv(write("blowup.csv", csv));
  ASSERT_TRUE(d.ok()) << d.error();
  for (int k = 100; k < 200; ++k)
    d->columns[1][static_cast<std::size_t>(k)] = 1e308;  // θ += ω·Ts grows past any S
  auto r = s->run(*d, s->params().defaults());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code(), kExitFailed);
  EXPECT_NE(r.error().find("step "), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("(t = "), std::string::npos) << r.error();
}

TEST(DataPolicy, UndefinedMetricsAreListedNeverNaN) {
  auto s = policy_heli();
  ASSERT_TRUE(s);
  auto d = read_csv(write("notruth.csv", "t,gyro,angle\n0,1,0\n0.02,1,0.1\n0.04,1,0.2\n"));
  ASSERT_TRUE(d.ok());
  auto r = s->run(*d, s->params().defaults());
  ASSERT_TRUE(r.ok()) << r.error();
  for (const auto& [k, v] : (*r)->metrics)
    EXPECT_TRUE(std::isfinite(v)) << k;
  EXPECT_EQ((*r)->undefined.count("rmse"), 1u);
  EXPECT_EQ((*r)->undefined.at("nees_mean"), "no truth column");
  const std::string json = metrics_to_json((*r)->metrics, (*r)->undefined);
  EXPECT_EQ(json.find("null"), std::string::npos);
  EXPECT_NE(json.find("\"undefined\""), std::string::npos);
}

}  // namespace
}  // namespace kfw
