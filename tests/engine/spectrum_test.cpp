#include "core/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/scenario.h"

namespace kfw {
namespace {

TEST(Spectrum, WhiteNoiseDensityIsFlatAtSigmaSquaredOverHalfFs) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 2.0);
  std::vector<double> x(1 << 16);
  for (auto& v : x)
    v = n(rng);
  auto psd = welch_psd(x, 100.0, 1024);
  ASSERT_TRUE(psd.ok());
  double mean = 0;
  for (std::size_t k = 1; k + 1 < psd->density.size(); ++k)
    mean += psd->density[k];
  mean /= static_cast<double>(psd->density.size() - 2);
  EXPECT_NEAR(mean, 4.0 / 50.0, 0.03 * 4.0 / 50.0);  // σ² / (fs/2)
  EXPECT_NEAR(*white_noise_variance(x, 100.0), 4.0, 0.1);
}

TEST(Spectrum, ASlowSignalUnderneathDoesNotBiasTheNoiseLevel) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 0.5);
  std::vector<double> x(1 << 15);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = 20.0 * std::sin(2 * std::numbers::pi * 0.3 * static_cast<double>(i) / 50.0) + n(rng);
  }
  EXPECT_NEAR(*white_noise_variance(x, 50.0), 0.25, 0.02);
}

TEST(Spectrum, BadInputIsAnError) {
  EXPECT_FALSE(welch_psd(std::vector<double>(100, 0.0), 10, 1024).ok());
  EXPECT_FALSE(welch_psd(std::vector<double>(4096, 0.0), 10, 1000).ok());
  std::vector<double> gap(4096, 1.0);
  gap[7] = std::nan("");
  EXPECT_NE(welch_psd(gap, 10).error().find("non-finite"), std::string::npos);
}

// Seed 000 eq. 3 on the simulator: the PSD reads back the engine-running noise levels.
TEST(Spectrum, HelicopterNoiseCommandReadsBackTheSimulatorSigmas) {
  auto s = make_scenario("helicopter");
  auto v = (*s)->params().defaults();
  v["sim.duration"] = 600;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  auto text = (*s)->command("noise", *d, v);
  ASSERT_TRUE(text.ok()) << text.error();
  EXPECT_NE(text->find("Q_suggested"), std::string::npos);
  const double sg = std::stod(text->substr(text->find("\"sigma_gyro\": ") + 14));
  const double sa = std::stod(text->substr(text->find("\"sigma_angle\": ") + 15));
  EXPECT_NEAR(sg, 8.2, 0.03 * 8.2);
  EXPECT_NEAR(sa, 1.4, 0.03 * 1.4);
}

}  // namespace
}  // namespace kfw
