// Seed 003: the ball tracking filter's constant-velocity model (eq. 12) and its steady-state gains,
// in closed form from the tracking index λ (seed 003 eq. 16, corrected: docs/reproductions.md) and
// from the DARE.
#pragma once

#include <vector>

#include "core/expected.h"
#include "core/types.h"

namespace kfw::ballbeam {

static constexpr int kPos = 0;  // ball position x, m
static constexpr int kVel = 1;  // ball velocity ẋ, m/s

struct TrackModel {
  Mat<2> F;          // [[1, Ts], [0, 1]]
  Vec<2> G;          // [Ts²/2, Ts]^T, also G^c (the input u^c = a3 θ enters like w)
  Mat<1, 2> H;       // [1, 0]
  Covariance<2> Qd;  // G Q G^T
};

// F, G = G^c, H and the discrete process covariance G Q G^T (seed 003, eq. 12–13, 15).
TrackModel track_model(double Ts_s, double Q);

// λ = Ts² √(Q/R) (seed 003, eq. 16; the paper prints √(R/Q), a typo).
double tracking_index(double Ts_s, double Q, double R);

struct AlphaBeta {
  double alpha = 0.0;
  double beta = 0.0;
};

// α = −(λ² + 8λ − (λ+4)√(λ²+8λ))/8, β = (λ² + 4λ − λ√(λ²+8λ))/4 (seed 003, eq. 16 as corrected
// in docs/reproductions.md). Evaluated in a cancellation-free form so that tiny λ keeps full
// precision.
AlphaBeta alpha_beta(double lambda);

struct SteadyTrackGain {
  double alpha = 0.0;  // K1
  double beta = 0.0;   // K2 · Ts
  Mat<2, 1> K;         // [α, β/Ts]^T
  Covariance<2> P_pred;
  Covariance<2> P_post;
};

// K = [α, β/Ts]^T from the DARE of the same model (seed 003, eq. 14–16 at steady state).
Expected<SteadyTrackGain> steady_gain_dare(double Ts_s, double Q, double R);

struct GainCurve {
  std::vector<double> lambda, alpha, beta;
};
// α(λ) and β(λ) on n log-spaced λ values in [lo, hi] (the α-β design curve).
GainCurve gain_curve(double lambda_lo, double lambda_hi, int n);

}  // namespace kfw::ballbeam
