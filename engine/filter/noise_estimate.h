// The generic noise command (issue 27): the white-noise variance of every column a scenario links
// to a parameter (Scenario::noise_links), read from the high-frequency part of the column's power
// spectral density (seed 000, eq. 3), and the value each linked parameter would need, checked
// against the parameter's range. `kfw-cli noise` prints it; it is written once, for every
// scenario and model file.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/param_spec.h"
#include "core/scenario.h"

namespace kfw {

// The band the variance is read from: above this fraction of each column's Nyquist frequency.
inline constexpr double kNoiseBandFraction = 0.5;
inline constexpr const char* kNoiseBand = "above half of Nyquist";
// Fewer finite samples than this in a linked column are refused (two segments of 32).
inline constexpr std::size_t kNoiseMinSamples = 64;

// One linked column as measured.
struct NoiseColumn {
  std::string name;
  double fs_hz = 0.0;       // its sample rate: the data's, or its own when it has gaps
  std::size_t samples = 0;  // its finite samples (gaps closed up)
  double variance = 0.0;  // σ² = S̄ · fs / 2, S̄ the mean one-sided PSD above the band's edge
};

// One linked parameter: its columns and the value their noise asks for.
struct NoiseSuggestion {
  std::string param;
  std::vector<NoiseColumn> columns;
  double needed = 0.0;   // the value the variances ask for (may lie outside the range)
  double value = 0.0;    // the proposal: `needed` within the parameter's range
  bool clamped = false;  // `needed` lies outside the range: `value` is its nearer end
};

struct NoiseEstimate {
  double fs_hz = 0.0;                        // the data's sample rate, 1 / median interval
  std::vector<NoiseSuggestion> suggestions;  // in the order of the links
  std::vector<std::string> notes;            // each clamped proposal, said in words
};

// Refused (exit 2, before any work) when the scenario links no column: the message names the
// preset (`path`) and the key to add.
Status check_noise_links(const Scenario& s, const std::string& path);

// Measures every linked column of `d` and proposes each linked parameter's value, the other
// parameters at `p`. A column with gaps (a channel that updates every m-th row) is measured on
// its own samples at its own rate. Errors name the file and the column, or the link's key.
Expected<NoiseEstimate> estimate_noise(const Scenario& s, const Dataset& d, const ParamValues& p);

// {"fs_hz", "band", then per link "KEY_suggested" and per column "sigma_COLUMN" (with
// "fs_hz_COLUMN" where the column's rate differs from the data's), and "notes" when any}.
std::string noise_to_json(const NoiseEstimate& e);

}  // namespace kfw
