#include "filter/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/scenario.h"
#include "document/preset.h"
#include "filter/noise_estimate.h"

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

// Welch by the definition: a plain DFT of each Hann-windowed, mean-removed half-overlapping
// segment, against the FFT-based estimate, bin by bin.
TEST(Spectrum, EqualsWelchByTheDefinition) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> x(100);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = std::cos(0.7 * static_cast<double>(i)) + n(rng);
  const std::size_t seg = 16;
  const double fs = 10.0;
  auto psd = welch_psd(x, fs, seg);
  ASSERT_TRUE(psd.ok());
  std::vector<double> w(seg), expect(seg / 2 + 1, 0.0);
  double wss = 0.0;
  for (std::size_t i = 0; i < seg; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(i) / seg);
    wss += w[i] * w[i];
  }
  int count = 0;
  for (std::size_t start = 0; start + seg <= x.size(); start += seg / 2, ++count) {
    double mean = 0.0;
    for (std::size_t i = 0; i < seg; ++i)
      mean += x[start + i] / seg;
    for (std::size_t k = 0; k <= seg / 2; ++k) {
      double re = 0.0, im = 0.0;
      for (std::size_t i = 0; i < seg; ++i) {
        const double a = -2 * std::numbers::pi * static_cast<double>(k * i) / seg;
        re += (x[start + i] - mean) * w[i] * std::cos(a);
        im += (x[start + i] - mean) * w[i] * std::sin(a);
      }
      expect[k] += (k == 0 || k == seg / 2 ? 1.0 : 2.0) * (re * re + im * im) / (fs * wss);
    }
  }
  ASSERT_EQ(psd->density.size(), expect.size());
  for (std::size_t k = 0; k < expect.size(); ++k) {
    EXPECT_NEAR(psd->density[k], expect[k] / count, 1e-12 * (1 + expect[k])) << "bin " << k;
    EXPECT_DOUBLE_EQ(psd->f_hz[k], fs * static_cast<double>(k) / seg);
  }
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
  auto p = load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  ASSERT_TRUE(p.ok()) << p.error();
  auto v = p->values;
  v["sim.duration"] = 600;
  auto d = p->instance->simulate(v);
  ASSERT_TRUE(d.ok());
  // The helicopter's own command became the generic one (issue 27): the same JSON.
  auto e = estimate_noise(*p->instance, *d, v);
  ASSERT_TRUE(e.ok()) << e.error();
  const std::string text = noise_to_json(*e);
  EXPECT_NE(text.find("Q_suggested"), std::string::npos);
  const double sg = std::stod(text.substr(text.find("\"sigma_gyro\": ") + 14));
  const double sa = std::stod(text.substr(text.find("\"sigma_angle\": ") + 15));
  EXPECT_NEAR(sg, 8.2, 0.03 * 8.2);
  EXPECT_NEAR(sa, 1.4, 0.03 * 1.4);
}

}  // namespace
}  // namespace kfw
