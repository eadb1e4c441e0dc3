// Power spectral density (Welch) and the white-noise level read from its high-frequency part
// (seed 000, eq. 3: the sensor noise variances are measured this way).
#pragma once

#include <cstddef>
#include <vector>

#include "core/expected.h"

namespace kfw {

struct Psd {
  std::vector<double> f_hz;     // 0 … fs/2
  std::vector<double> density;  // one-sided, units² / Hz
};

// Welch's method: Hann-windowed segments of `segment` samples (a power of two), 50 % overlap,
// mean removed per segment. Non-finite samples are not allowed (fill or cut gaps first).
Expected<Psd> welch_psd(const std::vector<double>& x, double fs_hz, std::size_t segment = 1024);

// The variance of the white noise in x, from the mean PSD above `fraction` × Nyquist:
// σ² = S̄ · fs / 2 for a one-sided density. A smooth signal underneath adds nothing there.
Expected<double> white_noise_variance(const std::vector<double>& x, double fs_hz,
                                      double fraction = 0.5, std::size_t segment = 1024);

}  // namespace kfw
