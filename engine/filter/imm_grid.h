// A grid of IMM modes that moves (seed 001, eq. 4: mode-parameter renewal), over any number of
// axes: the modes are the product grid, mode j = i₀ + n₀ (i₁ + n₁ (i₂ + …)), the first axis
// fastest. When the grid moves by d_a along axis a, the probability mass at each old grid value
// is shared between the two moved grid points around it (linear interpolation; mass beyond an
// end goes to that end).
#pragma once

#include <vector>

#include "core/types.h"

namespace kfw {

// W(i, i'): the share of old point i (at offset off[i]) that goes to point i' of the grid moved
// by d. Offsets ascending; rows sum to 1.
MatX grid_share_matrix(const std::vector<double>& off, double d);

// μ on the product grid with per-axis offsets `off`, re-expressed on the grid moved by d (one
// entry per axis): μ' = (⊗_a W_a)ᵀ μ, axis by axis. Σ μ is kept.
VecX grid_remap(const VecX& mu, const std::vector<std::vector<double>>& off,
                const std::vector<double>& d);

// The move as a mode transition: T(i, i') = Π_a W_a(i_a, i'_a). Rows sum to 1.
MatX grid_shift_transition(const std::vector<std::vector<double>>& off,
                           const std::vector<double>& d);

}  // namespace kfw
