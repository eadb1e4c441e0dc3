// The interacting multiple model (IMM) estimator (seed 001, Table 2; Bar-Shalom et al. 2001):
// r mode-matched linear Kalman filters, a Markov chain over the modes, mixing with spread terms,
// mode probability update and combination. Mode probabilities and likelihoods live in the log
// domain (log-sum-exp), so a mode whose likelihood underflows gets probability 0, never NaN.
//
// The cycle is split into small pieces (mixing weights → mixing → mode-matched filtering →
// probability update → combination) so a model with structure can run its own mode-matched
// filters (e.g. one small filter per independent axis block, mixed block by block with the same
// weights); imm_step() runs the whole cycle for plain per-mode linear models.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/expected.h"
#include "core/types.h"
#include "filter/kalman_filter.h"

namespace kfw {

// The Markov transition matrix p^{ij} = P(mode j at k | mode i at k−1). The "uniform" chain (one
// stay probability on the diagonal, the rest spread equally) mixes in O(r) instead of O(r²).
class MarkovChain {
 public:
  // p^{jj} = stay, p^{ij} = (1 − stay)/(r − 1). Errors name `markov.stay` when outside (0, 1].
  static Expected<MarkovChain> uniform(int modes, double stay);
  // Any row-stochastic r × r matrix (entries in [0, 1], rows summing to 1 within 1e-9).
  static Expected<MarkovChain> dense(const MatX& p);

  int modes() const { return modes_; }
  bool is_uniform() const { return uniform_; }
  double stay() const { return stay_; }
  double off() const { return off_; }
  // The full matrix (built for dense use and for tests).
  MatX matrix() const;

 private:
  int modes_ = 1;
  bool uniform_ = true;
  double stay_ = 1.0, off_ = 0.0;
  MatX p_;
};

// μ = exp(log μ), with probabilities below e^{−700} (≈ 1e−304) flushed to 0: subnormal numbers
// would make every later product ~100× slower, and such modes carry no weight anyway.
VecX imm_probabilities(const VecX& log_mu);

// Weights of one mixing stage (seed 001, Table 2, "calculation of the mixing probabilities").
struct ImmMixing {
  VecX log_c_bar;  // log c̄^j = log Σ_i p^{ij} μ^i: the predicted mode probabilities
  VecX mu;         // μ^i_{k−1}
  bool uniform = true;
  // Uniform chain: mixed^j = (1 − b_j) · (μ-weighted moments of all modes) + b_j · own moments,
  // b_j = (p^{jj} − p^{off}) μ^j / c̄^j; exactly 0 when below 1e-16, and then the mode's mixed
  // prior is the shared μ-weighted one.
  VecX own;
  MatX mu_ij;  // dense chain: μ^{i|j} = p^{ij} μ^i / c̄^j (column j sums to 1)
};

// Mixing probabilities from the chain and log μ_{k−1} (seed 001, Table 2).
ImmMixing imm_mixing(const MarkovChain& chain, const VecX& log_mu);

// Mixed initial conditions x^{0j}, P^{0j} with spread terms (seed 001, Table 2, "mixing").
// For the uniform chain the moments are taken about the μ-weighted mean, which keeps the
// spread terms accurate when the states are large (positions of 10 km, spreads of metres).
template <int N>
void imm_mix(const ImmMixing& w, const std::vector<Gaussian<N>>& in,
             std::vector<Gaussian<N>>& out) {
  const std::size_t r = in.size();
  out.resize(r);
  if (r == 0) return;
  const Eigen::Index n = in[0].x.rows();
  if (w.uniform) {
    Vec<N> mean = Vec<N>::Zero(n);
    for (std::size_t i = 0; i < r; ++i)
      mean.noalias() += w.mu(i) * in[i].x;
    Covariance<N> M = Covariance<N>::Zero(n, n);
    for (std::size_t i = 0; i < r; ++i) {
      if (w.mu(i) == 0.0) continue;
      const Vec<N> d = in[i].x - mean;
      M.noalias() += w.mu(i) * in[i].P;
      M.noalias() += (w.mu(i) * d) * d.transpose();
    }
    for (std::size_t j = 0; j < r; ++j) {
      const double b = w.own(j);
      if (b == 0.0) {
        out[j].x = mean;
        out[j].P = M;
        continue;
      }
      const Vec<N> d = in[j].x - mean;
      out[j].x = mean + b * d;
      out[j].P = (1.0 - b) * M + b * in[j].P;
      out[j].P.noalias() += (b * (1.0 - b) * d) * d.transpose();
    }
    return;
  }
  for (std::size_t j = 0; j < r; ++j) {
    Vec<N> x = Vec<N>::Zero(n);
    for (std::size_t i = 0; i < r; ++i)
      x.noalias() += w.mu_ij(i, j) * in[i].x;
    Covariance<N> P = Covariance<N>::Zero(n, n);
    for (std::size_t i = 0; i < r; ++i) {
      const double m = w.mu_ij(i, j);
      if (m == 0.0) continue;
      const Vec<N> d = in[i].x - x;
      P.noalias() += m * in[i].P;
      P.noalias() += (m * d) * d.transpose();
    }
    out[j].x = x;
    out[j].P = P;
  }
}

struct ImmProbabilities {
  VecX log_mu;         // log μ^j_k
  double log_c = 0.0;  // log c = log Σ_j Λ^j c̄^j: the log-likelihood of the measurement
  bool ok = true;      // false when no mode had a finite likelihood: μ_k = c̄ (prediction)
};

// μ^j = Λ^j c̄^j / c in the log domain (seed 001, Table 2, "mode probability update").
// A NaN log-likelihood counts as −∞ (the mode gets probability 0).
ImmProbabilities imm_update_probabilities(const VecX& log_c_bar, const VecX& log_likelihood);

// Σ_j μ^j x^j and Σ_j μ^j (P^j + (x^j − x)(x^j − x)^T) (seed 001, Table 2, "combination").
template <int N>
Gaussian<N> imm_combine(const std::vector<Gaussian<N>>& g, const VecX& mu) {
  const Eigen::Index n = g.empty() ? 0 : g[0].x.rows();
  Gaussian<N> c;
  c.x = Vec<N>::Zero(n);
  c.P = Covariance<N>::Zero(n, n);
  for (std::size_t j = 0; j < g.size(); ++j)
    c.x.noalias() += mu(j) * g[j].x;
  for (std::size_t j = 0; j < g.size(); ++j) {
    if (mu(j) == 0.0) continue;
    const Vec<N> d = g[j].x - c.x;
    c.P.noalias() += mu(j) * g[j].P;
    c.P.noalias() += (mu(j) * d) * d.transpose();
  }
  return c;
}

// log N(y; 0, S) from an innovation and S (seed 001, Table 2: Λ^j, in the log domain);
// −∞ when S is not positive definite.
template <int M>
double log_gaussian(const Vec<M>& y, const Covariance<M>& S) {
  Eigen::LLT<Covariance<M>> llt(S);
  if (llt.info() != Eigen::Success || !S.allFinite()) {
    return -std::numeric_limits<double>::infinity();
  }
  const auto& L = llt.matrixL();
  double log_det = 0.0;
  for (Eigen::Index i = 0; i < S.rows(); ++i)
    log_det += 2.0 * std::log(llt.matrixLLT()(i, i));
  const Vec<M> u = L.solve(y);
  return -0.5 * (u.squaredNorm() + log_det +
                 static_cast<double>(S.rows()) * std::log(2.0 * std::numbers::pi));
}

// The state of an IMM between steps: one Gaussian per mode and log μ.
template <int N>
struct ImmState {
  std::vector<Gaussian<N>> modes;
  VecX log_mu;
};

// A mode's linear model: x_k = F x_{k−1} + Bu + w (Q), z = H x + v (R).
template <int N, int M>
struct ImmModel {
  Mat<N, N> F;
  Vec<N> Bu;
  Covariance<N> Q;
  Mat<M, N> H;
  Covariance<M> R;
};

template <int N, int M>
struct ImmStep {
  ImmState<N> state;                  // posterior per mode, log μ_k
  std::vector<Update<N, M>> updates;  // per mode: innovation, S, K, NIS
  VecX log_likelihood;                // log Λ^j (−∞ where S was not positive definite)
  Gaussian<N> combined;               // x_{k|k}, P_{k|k}
  double log_c = 0.0;
  bool ok = true;  // false when no mode could use the measurement
};

// One full IMM cycle (seed 001, Table 2). `models` holds one model per mode (or a single model
// shared by all); `z` one measurement per mode (mode-dependent pseudo-measurements, seed 001)
// or a single one shared by all.
template <int N, int M>
ImmStep<N, M> imm_step(const ImmState<N>& s, const MarkovChain& chain,
                       const std::vector<ImmModel<N, M>>& models, const std::vector<Vec<M>>& z) {
  const std::size_t r = s.modes.size();
  ImmStep<N, M> out;
  const ImmMixing w = imm_mixing(chain, s.log_mu);
  std::vector<Gaussian<N>> mixed;
  imm_mix(w, s.modes, mixed);
  out.state.modes.resize(r);
  out.updates.resize(r);
  out.log_likelihood.resize(static_cast<Eigen::Index>(r));
  for (std::size_t j = 0; j < r; ++j) {
    const ImmModel<N, M>& m = models.size() == 1 ? models[0] : models[j];
    const Vec<M>& zj = z.size() == 1 ? z[0] : z[j];
    const Gaussian<N> pred = predict(mixed[j], m.F, m.Bu, m.Q);
    out.updates[j] = update(pred, zj, m.H, m.R);
    out.state.modes[j] = out.updates[j].post;
    out.log_likelihood(static_cast<Eigen::Index>(j)) =
        out.updates[j].ok ? log_gaussian<M>(out.updates[j].innovation, out.updates[j].S)
                          : -std::numeric_limits<double>::infinity();
  }
  const ImmProbabilities p = imm_update_probabilities(w.log_c_bar, out.log_likelihood);
  out.state.log_mu = p.log_mu;
  out.log_c = p.log_c;
  out.ok = p.ok;
  out.combined = imm_combine(out.state.modes, imm_probabilities(p.log_mu));
  return out;
}

}  // namespace kfw
