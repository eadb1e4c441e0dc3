// Mode-parameter renewal (seed 001, eq. 4) and what it does to the mode probabilities.
//
// Eq. 4 moves the whole grid by ΔR̄_k = Kp (R̂_{k−1} − mean R̄_{k−1}); the paper says neither what
// becomes of the mode probabilities μ^j nor at what rate Kp applies. Three readings
// (Renewal in radome_imm.h): `index` keeps μ on the mode index, so the estimate R̂ = Σ μ^j R̄^j
// jumps with the grid and the next renewal sees the same gap; `slope` shares the mass at each
// old slope between the two moved grid points around it (linear interpolation; mass beyond an
// edge goes to that edge), so the renewal moves the grid and not the estimate; `rate` applies Kp
// per second (ΔR̄ = Kp·Ts·(R̂ − R̄)) with μ by index; `mix` treats the shift as a mode transition
// composed with the Markov chain, so μ, the mode states and covariances move to the new grid in
// one IMM mixing (a mode keeps the state of the slope it now stands for). docs/reproductions.md
// (radome) compares them.
#pragma once

#include <vector>

#include "core/types.h"

namespace kfw::radome {

// Probabilities μ (mode j = a + n_ψ b) on the grid with offsets off_psi, off_theta, re-expressed
// on the same grid moved by (d_psi, d_theta): each old slope's mass goes to the moved grid's
// neighbours of that slope. Offsets ascending. Σ μ is kept.
// The grid shift as a mode transition: T(i, i') = share of old mode i (a + n_ψ b) that goes to
// mode i' of the moved grid, the product of the per-axis shares above. Rows sum to 1.
MatX shift_transition(const std::vector<double>& off_psi, const std::vector<double>& off_theta,
                      double d_psi, double d_theta);

VecX remap_probabilities(const VecX& mu, const std::vector<double>& off_psi,
                         const std::vector<double>& off_theta, double d_psi, double d_theta);

}  // namespace kfw::radome
