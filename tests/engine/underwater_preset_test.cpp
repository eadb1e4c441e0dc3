// Seed 004's numbers on its seed preset (presets/underwater.json, the model file that replaced the
// built-in underwater scenario in issue 30): Table 13's position RMSE, Table 14's outlier counts
// and the position NEES against truth, for the AS / SC / SI update schemes. The same tests ran
// through the built-in as UnderwaterEkf.* (the EKF itself is still tested as the oracle,
// underwater_ekf_test.cpp; the file equals it to 1e-9, model_groups_test.cpp).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "common/dataset_edit.h"
#include "core/dataset.h"
#include "core/scenario.h"
#include "core/types.h"
#include "document/preset.h"

namespace kfw {
namespace underwater_preset_test {
namespace {

const std::string kUnderwaterPreset = KFW_SOURCE_DIR "/presets/underwater.json";

// The ranges the χ² gate rejected, over the four channels (the built-in's ranges_rejected).
double underwater_gated(const Metrics& m) {
  return m.at("gated.range1") + m.at("gated.range2") + m.at("gated.range3") + m.at("gated.range4");
}

// The default preset (every uncertainty on, high correlation, ±1 m outliers, asynchronous) lands
// in the band of seed 004, Table 13 (RMSE 0.13–0.20 m) or better, and catches ≥ 94 % of outliers
// (Table 14: 276/276, 264/276, 276/276). The bound was 95 % before the simulators drew from the
// random-number specification (CHANGES.md, issue 27): the default seed 4 catches 262 (AS), 266
// (SC), 263 (SI) of 276 (was 269, 271, 269), RMSE 0.084, 0.074, 0.084 m. The built-in's pos_mean
// ≤ rmse is gone with its metric; rmse is the distance error |X̂ − X| of Table 13, not an axis.
TEST(UnderwaterPreset, DefaultPresetMatchesTable13And14) {
  auto preset = load_preset(kUnderwaterPreset);
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& sc = *preset->instance;
  const ParamValues& v = preset->values;
  const auto d = sc.simulate(v);
  ASSERT_TRUE(d) << d.error();
  for (double scheme : {0.0, 1.0, 2.0}) {
    ParamValues w = v;
    w["scheme"] = scheme;
    const auto r = sc.run(*d, w);
    ASSERT_TRUE(r) << r.error();
    const Metrics& m = (*r)->metrics;
    EXPECT_LT(m.at("rmse"), 0.20) << scheme;
    EXPECT_NEAR(m.at("rmse"), m.at("derived.pos_err.rms"), 1e-12 * m.at("rmse"));
    EXPECT_EQ(m.at("outliers_injected"), 276.0);
    EXPECT_GE(m.at("outliers_detected"), 0.94 * 276.0) << scheme;
  }
}

// Without outlier1..4 nobody knows which rejections were outliers: the counts are undefined (with
// the reason), not "every rejection is a false alarm".
TEST(UnderwaterPreset, OutlierCountsAreUnknownWithoutInjectedColumns) {
  auto preset = load_preset(kUnderwaterPreset);
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& sc = *preset->instance;
  const ParamValues& v = preset->values;
  const auto d = sc.simulate(v);
  ASSERT_TRUE(d) << d.error();
  const auto with = sc.run(*d, v);
  ASSERT_TRUE(with) << with.error();
  const Metrics& mw = (*with)->metrics;
  EXPECT_EQ(mw.at("outliers_injected"), 276.0);
  EXPECT_TRUE(std::isfinite(mw.at("outliers_false_alarm")));
  // Every rejected range is either a caught outlier or a false alarm.
  EXPECT_EQ(underwater_gated(mw), mw.at("outliers_detected") + mw.at("outliers_false_alarm"));

  const Dataset bare = test::without_columns(*d, {"outlier1", "outlier2", "outlier3", "outlier4"});
  const auto r = sc.run(bare, v);
  ASSERT_TRUE(r) << r.error();
  const Metrics& m = (*r)->metrics;
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    EXPECT_EQ(m.count(k), 0U) << k;
    ASSERT_TRUE((*r)->undefined.count(k)) << k;
    EXPECT_NE((*r)->undefined.at(k).find("outlier column"), std::string::npos) << k;
  }
  // The gate still works; only the bookkeeping is unknown.
  EXPECT_EQ(underwater_gated(m), underwater_gated(mw));
  EXPECT_GT(underwater_gated(m), 200.0);
  // One column missing: the built-in called all counts unknown; the file counts the three other
  // channels and names the one it left out (issue 27, ModelGroups.MissingOutlierColumns…).
  const auto one = sc.run(test::without_columns(*d, {"outlier3"}), v);
  ASSERT_TRUE(one) << one.error();
  EXPECT_LT((*one)->metrics.at("outliers_injected"), 276.0);
  EXPECT_GT((*one)->metrics.at("outliers_injected"), 0.0);
  const auto& warnings = (*one)->warnings;
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& x) {
    return x.find("'outlier3' is not in the data") != std::string::npos;
  }));
}

// The position error and its covariance at row k of the run's table and the data's truth.
double underwater_quadratic_form(const Dataset& out, const Dataset& d, std::size_t k) {
  Covariance<3> P;
  const double xy = out.col("P.x.y")[k], xz = out.col("P.x.z")[k], yz = out.col("P.y.z")[k];
  P << out.col("P.x")[k], xy, xz, xy, out.col("P.y")[k], yz, xz, yz, out.col("P.z")[k];
  const Vec<3> e(out.col("x.x")[k] - d.col("x_true")[k], out.col("x.y")[k] - d.col("y_true")[k],
                 out.col("x.z")[k] - d.col("z_true")[k]);
  return e.dot(P.inverse() * e);
}

// NEES of (x, y, z) against truth: 3 dof, the textbook quadratic form, NaN where truth is missing.
TEST(UnderwaterPreset, NeesOfThePositionAgainstTruth) {
  auto preset = load_preset(kUnderwaterPreset);
  ASSERT_TRUE(preset.ok()) << preset.error();
  const Scenario& sc = *preset->instance;
  const ParamValues& v = preset->values;
  auto d = sc.simulate(v);
  ASSERT_TRUE(d) << d.error();
  // Truth lost for a stretch of rows.
  auto& xt = d->columns[static_cast<std::size_t>(d->index("x_true"))];
  for (std::size_t k = 1000; k < 1100; ++k)
    xt[k] = kNoSample;
  for (double scheme : {0.0, 1.0, 2.0}) {
    ParamValues w = v;
    w["scheme"] = scheme;
    const auto run = sc.run(*d, w);
    ASSERT_TRUE(run) << run.error();
    const RunResult& r = **run;
    const NeesSeries s = r.nees_series();
    EXPECT_EQ(s.dof, 3.0);
    ASSERT_EQ(s.nees.size(), d->rows());
    for (std::size_t k = 1000; k < 1100; ++k)
      EXPECT_TRUE(std::isnan(s.nees[k])) << k;
    std::size_t finite = 0;
    for (double e : s.nees)
      finite += std::isfinite(e) ? 1 : 0;
    EXPECT_EQ(finite, d->rows() - 100);
    // The quadratic form with the full covariance of the row.
    const Dataset out = r.table();
    ASSERT_EQ(out.rows(), d->rows());
    for (std::size_t k : {std::size_t{0}, d->rows() / 2, d->rows() - 1}) {
      EXPECT_NEAR(s.nees[k], underwater_quadratic_form(out, *d, k), 1e-9 * (1.0 + s.nees[k])) << k;
    }
    // A sensible mean on the default run: nees_mean is NEES / dof, near 1 (R carries the common
    // range noise σ_c² as if it were white, so P is not far from the error).
    const double mean = r.metrics.at("nees_mean");
    EXPECT_GT(mean, 0.5) << scheme;
    EXPECT_LT(mean, 1.5) << scheme;
  }
  // Without any truth there is no NEES at all.
  const auto bare = sc.run(test::without_columns(*d, {"x_true", "y_true", "z_true"}), v);
  ASSERT_TRUE(bare) << bare.error();
  EXPECT_TRUE((*bare)->nees_series().nees.empty());
  EXPECT_EQ((*bare)->metrics.count("nees_mean"), 0u);
  EXPECT_FALSE((*bare)->undefined.at("nees_mean").empty());
}

}  // namespace
}  // namespace underwater_preset_test
}  // namespace kfw
