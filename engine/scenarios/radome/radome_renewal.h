// Mode-parameter renewal (seed 001, eq. 4) and what it does to the mode probabilities.
//
// Eq. 4 moves the whole grid by ΔR̄_k = Kp (R̂_{k−1} − mean R̄_{k−1}); the paper does not say what
// becomes of the mode probabilities μ^j. Kept on the mode index (`keep_index`), they follow the
// grid: the estimate R̂ = Σ μ^j R̄^j jumps by ΔR̄ with it, the next renewal sees the same gap, and
// the grid runs away from the estimate until the likelihoods catch up (±0.13–0.27 for truth B).
// Kept on the slope value (`keep_slope`, the default), the probability mass at each old slope is
// shared between the two new grid points around it (linear interpolation; mass beyond an edge goes
// to that edge), so the renewal moves the grid and not the estimate: the grid centre approaches
// R̂ at the rate Kp and the grid stays about its half-width around the estimate (Figs. 7–9).
#pragma once

#include <vector>

#include "core/types.h"

namespace kfw::radome {

// Probabilities μ (mode j = a + n_ψ b) on the grid with offsets off_psi, off_theta, re-expressed
// on the same grid moved by (d_psi, d_theta): each old slope's mass goes to the moved grid's
// neighbours of that slope. Offsets ascending. Σ μ is kept.
VecX remap_probabilities(const VecX& mu, const std::vector<double>& off_psi,
                         const std::vector<double>& off_theta, double d_psi, double d_theta);

}  // namespace kfw::radome
