#include "core/spectrum.h"

#include <cmath>
#include <complex>
#include <numbers>

namespace kfw {

namespace {

// In-place iterative radix-2 FFT.
void fft(std::vector<std::complex<double>>& a) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1)
      j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = -2.0 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0);
      for (std::size_t k = 0; k < len / 2; ++k) {
        const auto u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
        w *= wl;
      }
    }
  }
}

}  // namespace

Expected<Psd> welch_psd(const std::vector<double>& x, double fs_hz, std::size_t segment) {
  if (segment < 8 || (segment & (segment - 1)) != 0)
    return Error{"PSD: segment must be a power of two >= 8"};
  if (!(fs_hz > 0)) return Error{"PSD: sample rate must be positive"};
  if (x.size() < segment) {
    return Error{"PSD: need at least " + std::to_string(segment) + " samples, have " +
                 std::to_string(x.size())};
  }
  for (double v : x) {
    if (!std::isfinite(v)) return Error{"PSD: the signal has missing or non-finite samples"};
  }
  std::vector<double> w(segment);
  double wss = 0.0;
  for (std::size_t i = 0; i < segment; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) /
                                static_cast<double>(segment));
    wss += w[i] * w[i];
  }
  Psd out;
  const std::size_t bins = segment / 2 + 1;
  out.density.assign(bins, 0.0);
  std::size_t count = 0;
  std::vector<std::complex<double>> buf(segment);
  for (std::size_t start = 0; start + segment <= x.size(); start += segment / 2) {
    double mean = 0.0;
    for (std::size_t i = 0; i < segment; ++i)
      mean += x[start + i];
    mean /= static_cast<double>(segment);
    for (std::size_t i = 0; i < segment; ++i)
      buf[i] = (x[start + i] - mean) * w[i];
    fft(buf);
    for (std::size_t k = 0; k < bins; ++k) {
      const double scale = (k == 0 || k == segment / 2) ? 1.0 : 2.0;  // one-sided
      out.density[k] += scale * std::norm(buf[k]) / (fs_hz * wss);
    }
    ++count;
  }
  for (auto& d : out.density)
    d /= static_cast<double>(count);
  for (std::size_t k = 0; k < bins; ++k) {
    out.f_hz.push_back(fs_hz * static_cast<double>(k) / static_cast<double>(segment));
  }
  return out;
}

Expected<double> white_noise_variance(const std::vector<double>& x, double fs_hz, double fraction,
                                      std::size_t segment) {
  if (!(fraction > 0.0 && fraction < 1.0)) return Error{"PSD: fraction must be in (0, 1)"};
  auto psd = welch_psd(x, fs_hz, segment);
  if (!psd) return psd.err();
  const double f0 = fraction * fs_hz / 2.0;
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k + 1 < psd->f_hz.size(); ++k) {  // the Nyquist bin is one-sided-odd
    if (psd->f_hz[k] >= f0) {
      sum += psd->density[k];
      ++n;
    }
  }
  if (n == 0) return Error{"PSD: no frequency bins above the cutoff"};
  return sum / static_cast<double>(n) * fs_hz / 2.0;
}

}  // namespace kfw
