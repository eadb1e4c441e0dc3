#include "filter/imm.h"

#include <algorithm>
#include <limits>
#include <string>

namespace kfw {

namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();

// log Σ exp(v), −∞ when every entry is −∞.
double log_sum_exp(const VecX& v) {
  double m = kNegInf;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    m = std::max(m, v(i));
  if (!std::isfinite(m)) return kNegInf;
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    s += std::exp(v(i) - m);
  return m + std::log(s);
}

}  // namespace

Expected<MarkovChain> MarkovChain::uniform(int modes, double stay) {
  if (modes < 1) return Error{"IMM needs at least one mode, got " + std::to_string(modes)};
  if (!(stay > 0.0 && stay <= 1.0)) {
    return Error{"markov.stay must be in (0, 1], got " + std::to_string(stay)};
  }
  MarkovChain c;
  c.modes_ = modes;
  c.uniform_ = true;
  c.stay_ = modes == 1 ? 1.0 : stay;
  c.off_ = modes == 1 ? 0.0 : (1.0 - stay) / static_cast<double>(modes - 1);
  return c;
}

Expected<MarkovChain> MarkovChain::dense(const MatX& p) {
  if (p.rows() < 1 || p.rows() != p.cols()) return Error{"Markov matrix must be square, r >= 1"};
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    for (Eigen::Index j = 0; j < p.cols(); ++j) {
      if (!(p(i, j) >= 0.0 && p(i, j) <= 1.0)) {
        return Error{"Markov matrix entry (" + std::to_string(i) + ", " + std::to_string(j) +
                     ") is not a probability"};
      }
    }
    if (std::abs(p.row(i).sum() - 1.0) > 1e-9) {
      return Error{"Markov matrix row " + std::to_string(i) + " does not sum to 1"};
    }
  }
  MarkovChain c;
  c.modes_ = static_cast<int>(p.rows());
  c.uniform_ = false;
  c.p_ = p;
  return c;
}

MatX MarkovChain::matrix() const {
  if (!uniform_) return p_;
  MatX p = MatX::Constant(modes_, modes_, off_);
  p.diagonal().setConstant(stay_);
  return p;
}

VecX imm_probabilities(const VecX& log_mu) {
  VecX mu(log_mu.size());
  for (Eigen::Index j = 0; j < mu.size(); ++j)
    mu(j) = log_mu(j) < -700.0 ? 0.0 : std::exp(log_mu(j));
  return mu;
}

ImmMixing imm_mixing(const MarkovChain& chain, const VecX& log_mu) {
  const Eigen::Index r = log_mu.size();
  ImmMixing w;
  w.mu = imm_probabilities(log_mu);
  w.log_c_bar.resize(r);
  w.uniform = chain.is_uniform();
  if (w.uniform) {
    // c̄^j = off · Σμ + (stay − off) μ^j with Σμ = 1.
    const double s = chain.stay(), q = chain.off();
    w.own.resize(r);
    for (Eigen::Index j = 0; j < r; ++j) {
      const double c = q + (s - q) * w.mu(j);
      if (c > 0.0) {
        w.log_c_bar(j) = std::log(c);
        // Below 1e-16 the own-moment weight is under double resolution of the mixed moments:
        // 0 makes the mode's mixed prior exactly the shared one (and lets callers share work).
        const double b = (s - q) * w.mu(j) / c;
        w.own(j) = std::abs(b) < 1e-16 ? 0.0 : b;
      } else {
        // stay = 1 and μ^j = 0: the mode stays dead; keep its own (unused) moments.
        w.log_c_bar(j) = kNegInf;
        w.own(j) = 1.0;
      }
    }
    return w;
  }
  const MatX p = chain.matrix();
  w.mu_ij.resize(r, r);
  for (Eigen::Index j = 0; j < r; ++j) {
    const double c = p.col(j).dot(w.mu);
    if (c > 0.0) {
      w.log_c_bar(j) = std::log(c);
      w.mu_ij.col(j) = p.col(j).cwiseProduct(w.mu) / c;
    } else {
      w.log_c_bar(j) = kNegInf;
      w.mu_ij.col(j).setZero();
      w.mu_ij(j, j) = 1.0;
    }
  }
  return w;
}

ImmProbabilities imm_update_probabilities(const VecX& log_c_bar, const VecX& log_likelihood) {
  ImmProbabilities p;
  VecX v(log_c_bar.size());
  for (Eigen::Index j = 0; j < v.size(); ++j) {
    const double l = std::isnan(log_likelihood(j)) ? kNegInf : log_likelihood(j);
    v(j) = log_c_bar(j) + l;
    if (std::isnan(v(j))) v(j) = kNegInf;  // −∞ + ∞ cannot happen with finite c̄; be safe
  }
  p.log_c = log_sum_exp(v);
  if (!std::isfinite(p.log_c)) {
    // No mode explains the measurement: keep the predicted probabilities, report it.
    p.ok = false;
    const double norm = log_sum_exp(log_c_bar);
    p.log_mu = log_c_bar.array() - norm;
    return p;
  }
  p.log_mu = v.array() - p.log_c;
  return p;
}

}  // namespace kfw
