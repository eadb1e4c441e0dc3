#include "filter/consistency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/statistics.h"

namespace kfw {
namespace {

std::vector<double> ar1(double phi, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> x(n);
  double prev = 0.0;
  for (auto& v : x)
    prev = v = phi * prev + e(rng);
  return x;
}

TEST(Consistency, WhiteNoisePassesLjungBoxColouredFails) {
  int rejected = 0;
  for (unsigned seed = 1; seed <= 20; ++seed)
    rejected += ljung_box(ar1(0.0, 2000, seed)).p_value < 0.01;
  EXPECT_LE(rejected, 2);  // ~1 % false alarms expected
  const auto w = ljung_box(ar1(0.5, 2000, 3));
  EXPECT_LT(w.p_value, 1e-6);
  EXPECT_NEAR(w.acf[1], 0.5, 0.06);
  EXPECT_NEAR(w.band, 1.96 / std::sqrt(2000.0), 1e-12);
}

TEST(Consistency, AutocorrelationUsesTheChannelsOwnRate) {
  // NaN between samples (a slower sensor) must not change the result.
  auto x = ar1(0.7, 500, 5);
  std::vector<double> sparse;
  for (double v : x) {
    sparse.push_back(v);
    sparse.push_back(std::nan(""));
  }
  const auto a = autocorrelation(x, 5), b = autocorrelation(sparse, 5);
  for (std::size_t k = 0; k <= 5; ++k)
    EXPECT_DOUBLE_EQ(a[k], b[k]);
  EXPECT_DOUBLE_EQ(a[0], 1.0);
}

TEST(Consistency, NisBoundsAndMovingAverage) {
  const auto b1 = nis_bounds(1.0);
  EXPECT_NEAR(b1.lo, chi2_quantile(0.025, 1), 1e-12);
  EXPECT_NEAR(b1.hi, chi2_quantile(0.975, 1), 1e-12);
  const auto b50 = nis_bounds(3.0, 50);
  EXPECT_NEAR(b50.lo, chi2_quantile(0.025, 150) / 50, 1e-12);
  EXPECT_LT(b50.hi - b50.lo, b1.hi - b1.lo);
  const double nan = std::nan("");
  const auto m = moving_average_finite({1, nan, 3, 5, nan, 7}, 2);
  EXPECT_TRUE(std::isnan(m[0]) && std::isnan(m[1]) && std::isnan(m[4]));
  EXPECT_DOUBLE_EQ(m[2], 2.0);
  EXPECT_DOUBLE_EQ(m[3], 4.0);
  EXPECT_DOUBLE_EQ(m[5], 6.0);
}

}  // namespace
}  // namespace kfw
