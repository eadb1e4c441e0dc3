// kfw-cli as a user runs it: JSON fields, files written, one-line errors with non-zero exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_runner.h"
#include "core/dataset.h"
#include "data/csv.h"

namespace {

using kfw::testing::cli;

const std::string kHelicopter = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";

// presets/helicopter.json is a model file (issue 27): the closed forms are its derived scalars,
// the DARE's gain its K entry; the built-in's keys are in CHANGES.md.
TEST(HelicopterCli, GainPrintsClosedFormAndDare) {
  auto o = cli("gain " + kHelicopter + " --set m=25");
  ASSERT_EQ(o.code, 0) << o.text;
  auto j = nlohmann::json::parse(o.text);
  for (const char* k : {"derived.k1", "derived.p11_over_R", "K.theta.angle", "derived.beta"})
    ASSERT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["derived.k1"].get<double>(), j["K.theta.angle"].get<double>(), 1e-8);
  EXPECT_NEAR(j["derived.beta"].get<double>(), 25 * 0.02 * 0.02 * 67.24 / 1.96, 1e-9);
}

TEST(HelicopterCli, RunWritesMetricsAndEstimates) {
  const std::string dir = ::testing::TempDir();
  const std::string est = dir + "/kfw_est.csv", met = dir + "/kfw_met.json";
  const std::string data = std::string(KFW_SOURCE_DIR) + "/data/helicopter.csv";
  auto o = cli("run " + kHelicopter + " --data " + data + " --out " + est + " --metrics " + met);
  ASSERT_EQ(o.code, 0) << o.text;
  auto j = nlohmann::json::parse(o.text);
  for (const char* k : {"rmse", "rmse.theta", "derived.k1", "nis_mean"}) {
    ASSERT_TRUE(j.contains(k) && j[k].is_number()) << k;
  }
  // The filter beats its angle sensor (the built-in's rmse_sensor, computed here).
  auto in = kfw::read_csv(data);
  ASSERT_TRUE(in.ok()) << in.error();
  const auto& angle = in->col("angle");
  const auto& truth = in->col("truth");
  double sum = 0;
  for (std::size_t k = 0; k < angle.size(); ++k)
    sum += (angle[k] - truth[k]) * (angle[k] - truth[k]);
  EXPECT_LT(j["rmse"].get<double>(), std::sqrt(sum / static_cast<double>(angle.size())));
  auto d = kfw::read_csv(est);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->rows(), 6001u);
  EXPECT_TRUE(d->has("x.theta") && d->has("P.theta") && d->has("y.angle") && d->has("nis.angle"));
  EXPECT_TRUE(std::filesystem::exists(met));
}

TEST(HelicopterCli, SimulateIsReproducible) {
  const std::string a = ::testing::TempDir() + "/kfw_a.csv",
                    b = ::testing::TempDir() + "/kfw_b.csv";
  ASSERT_EQ(cli("simulate helicopter --seed 5 --set sim.duration=10 --out " + a).code, 0);
  ASSERT_EQ(cli("simulate helicopter --seed 5 --set sim.duration=10 --out " + b).code, 0);
  auto da = kfw::read_csv(a), db = kfw::read_csv(b);
  ASSERT_TRUE(da.ok() && db.ok());
  EXPECT_EQ(da->columns, db->columns);
  EXPECT_EQ(da->rows(), 501u);
}

TEST(HelicopterCli, BadInputExitsNonZeroWithOneLine) {
  struct Case {
    std::string args, fragment;
  };
  const std::string bad_csv = ::testing::TempDir() + "/kfw_bad.csv";
  {
    FILE* f = fopen(bad_csv.c_str(), "w");
    fputs("t,gyro,angle\n0,1,2\n0.01,2,3\n0.005,1,1\n", f);
    fclose(f);
  }
  for (const Case& c :
       {Case{"run " + kHelicopter + " --set bogus=1", "unknown parameter 'bogus'"},
        Case{"run " + kHelicopter + " --set R=-3", "'R' = -3 is out of range"},
        Case{"run " + kHelicopter + " --set m=2.5", "must be a whole number"},
        Case{"run " + kHelicopter + " --data /no/such.csv", "/no/such.csv: cannot open"},
        Case{"run " + kHelicopter + " --data " + bad_csv, ":4:1: time is not increasing"},
        Case{"run /no/preset.json", "cannot open preset"}, Case{"frobnicate", "unknown command"},
        Case{"simulate helicopter", "--out is required"}}) {
    auto o = cli(c.args);
    EXPECT_NE(o.code, 0) << c.args;
    EXPECT_NE(o.text.find(c.fragment), std::string::npos) << c.args << " → " << o.text;
    EXPECT_EQ(std::count(o.text.begin(), o.text.end(), '\n'), 1) << o.text;
  }
}

}  // namespace
