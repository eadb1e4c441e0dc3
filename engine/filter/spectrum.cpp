#include "filter/spectrum.h"

#include <fftw3.h>
#include <cmath>

#include <mutex>
#include <numbers>

namespace kfw {

namespace {

// FFTW's planner is not thread-safe (runs of several seeds compute spectra at once); executing a
// plan is.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

// A real-to-complex transform of `n` samples on its own FFTW buffers.
class RealFft {
 public:
  explicit RealFft(std::size_t n)
      : in_(static_cast<double*>(fftw_malloc(sizeof(double) * n))),
        out_(static_cast<fftw_complex*>(fftw_malloc(sizeof(fftw_complex) * (n / 2 + 1)))) {
    std::lock_guard<std::mutex> lock(planner_mutex());
    plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(n), in_, out_, FFTW_ESTIMATE);
  }
  ~RealFft() {
    {
      std::lock_guard<std::mutex> lock(planner_mutex());
      fftw_destroy_plan(plan_);
    }
    fftw_free(in_);
    fftw_free(out_);
  }
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  double* input() { return in_; }
  void run() { fftw_execute(plan_); }
  // |X_k|² of the last run, k = 0 … n/2.
  double power(std::size_t k) const { return out_[k][0] * out_[k][0] + out_[k][1] * out_[k][1]; }

 private:
  double* in_;
  fftw_complex* out_;
  fftw_plan plan_;
};

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
  RealFft fft(segment);
  double* buf = fft.input();
  for (std::size_t start = 0; start + segment <= x.size(); start += segment / 2) {
    double mean = 0.0;
    for (std::size_t i = 0; i < segment; ++i)
      mean += x[start + i];
    mean /= static_cast<double>(segment);
    for (std::size_t i = 0; i < segment; ++i)
      buf[i] = (x[start + i] - mean) * w[i];
    fft.run();
    for (std::size_t k = 0; k < bins; ++k) {
      const double scale = (k == 0 || k == segment / 2) ? 1.0 : 2.0;  // one-sided
      out.density[k] += scale * fft.power(k) / (fs_hz * wss);
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
