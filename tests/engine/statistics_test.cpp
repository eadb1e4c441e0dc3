#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace kfw {
namespace {

TEST(Statistics, Chi2QuantilesMatchTables) {
  EXPECT_NEAR(chi2_quantile(0.975, 1), 5.02389, 1e-4);
  EXPECT_NEAR(chi2_quantile(0.025, 1), 0.000982069, 1e-8);
  EXPECT_NEAR(chi2_quantile(0.95, 3), 7.81473, 1e-4);
  EXPECT_NEAR(chi2_quantile(0.5, 2), 2 * std::log(2.0), 1e-10);
  EXPECT_NEAR(chi2_cdf(chi2_quantile(0.3, 7.5), 7.5), 0.3, 1e-10);
  EXPECT_TRUE(std::isnan(chi2_quantile(1.5, 1)));
}

TEST(Statistics, NanAwareSummaries) {
  const double nan = std::nan("");
  EXPECT_DOUBLE_EQ(mean_finite({1, nan, 3}), 2.0);
  EXPECT_DOUBLE_EQ(rmse_finite({1, 2, nan}, {1, 4, 0}), std::sqrt(2.0));
  EXPECT_TRUE(std::isnan(rmse_finite({nan}, {1})));
  EXPECT_DOUBLE_EQ(last_finite({1, 2, nan}), 2.0);
  EXPECT_EQ(count_finite({1, nan, 2}), 2u);
  EXPECT_DOUBLE_EQ(fraction_inside({0.5, 100, nan, 1.0}, 1), 2.0 / 3.0);
}

}  // namespace
}  // namespace kfw
